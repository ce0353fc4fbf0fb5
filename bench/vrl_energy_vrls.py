import sys, collections, math
rows=[l.split() for l in open(sys.argv[1]) if len(l.split())==7]
P=len(set(r[0] for r in rows))
E=[float(r[5]) for r in rows]; tot=sum(E)
print(f"# {P} passes, {len(rows)} VRLs; mean image energy per pass {tot/P:.5g} (ref {sys.argv[2]})")
# by bounce
b=collections.defaultdict(lambda:[0,0.0])
def bk(k):
    k=int(k); return "0" if k==0 else ("1-3" if k<=3 else ("4-15" if k<=15 else ("16-63" if k<=63 else "64+")))
for r,e in zip(rows,E): b[bk(r[2])][0]+=1; b[bk(r[2])][1]+=e
print("| VRL bounce | share of VRLs | share of energy |"); print("|---|---:|---:|")
for k in ["0","1-3","4-15","16-63","64+"]:
    if k in b: print(f"| {k} | {b[k][0]/len(rows):.3f} | {b[k][1]/tot:.3f} |")
# per path energy
pe=collections.defaultdict(float)
for r,e in zip(rows,E): pe[(r[0],r[1])]+=e
v=sorted(pe.values()); n=len(v)
print(f"# light paths: {n}; top 1% of paths hold {sum(v[-max(1,n//100):])/sum(v):.1%} of the energy, top 0.1% {sum(v[-max(1,n//1000):])/sum(v):.1%}; paths with zero energy {sum(1 for x in v if x==0)/n:.1%}")
# top VRLs: attributes
idx=sorted(range(len(rows)),key=lambda i:-E[i]); top=idx[:max(10,len(rows)//1000)]
print(f"# top {len(top)} VRLs (0.1%) hold {sum(E[i] for i in top)/tot:.1%} of the energy")
def stats(ids,name):
    L=[float(rows[i][3]) for i in ids]; T=[float(rows[i][6]) for i in ids]; B=[int(rows[i][2]) for i in ids]
    L.sort(); T.sort(); B.sort()
    print(f"| {name} | {B[len(B)//2]} | {L[len(L)//2]:.3g} | {T[len(T)//2]:.3g} | {sum(1 for t in T if t>0.5)/len(T):.2f} |")
print("| VRLs | median bounce | median length | median best T to camera | share with T > 0.5 |"); print("|---|---:|---:|---:|---:|")
stats(top,"top 0.1% by energy"); stats(range(len(rows)),"all")
