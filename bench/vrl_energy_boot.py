import sys, random, math
# boot.py REPS_FILE REF [label]: per-pass values (lines "rep i v"); energy of the mean of N passes, bootstrap
vals=[float(l.split()[2]) for l in open(sys.argv[1]) if l.startswith('rep ')]
ref=float(sys.argv[2]); n=len(vals); random.seed(1)
m=sum(vals)/n; sd=math.sqrt(sum((v-m)**2 for v in vals)/(n-1))
s=sorted(vals)
print(f"# {sys.argv[3] if len(sys.argv)>3 else sys.argv[1]}: {n} passes, mean/ref {m/ref:.3f} +- {sd/math.sqrt(n)/ref:.3f}, "
      f"median pass/ref {s[n//2]/ref:.3f}, zero passes {sum(1 for v in vals if v==0)/n:.1%}, largest pass/ref {s[-1]/ref:.1f}, "
      f"top 1% of passes hold {sum(s[-max(1,n//100):])/sum(s):.1%} of the sum")
# tail index (Hill estimator on the top 5%)
k=max(5,n//20); top=s[-k:]; x0=s[-k-1] if s[-k-1]>0 else top[0]
if x0>0:
    hill=k/sum(math.log(v/x0) for v in top)
    print(f"# Hill tail index (top {k}): {hill:.2f} (< 2: infinite variance)")
print("| passes | median energy | 10% | 90% | mean energy |")
print("|---:|---:|---:|---:|---:|")
N=1
while N<=n:
    B=400
    es=sorted(sum(random.choice(vals) for _ in range(N))/N/ref for _ in range(B))
    print(f"| {N} | {es[B//2]:.3f} | {es[B//10]:.3f} | {es[9*B//10]:.3f} | {sum(es)/B:.3f} |")
    N*=4 if N<n//4 else 2
    if N>n: break
