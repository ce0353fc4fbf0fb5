#!/usr/bin/env python3
"""Scores bench/vlclass_defaults.sh renders at equal CPU (issue 13, session 6).

usage: vlclass_summary.py VBL REFDIR OUTDIR [OUTDIR ...]
Per render: `vbl diff IMG REFDIR/SCENE.exr --json` (rMAE per pixel, vbl diff's definition) of the
beauty, volume_from_volume (vfv) and volume_direct (vd). Per scene and config over seeds: the mean
CPU seconds and the mean of rMAE x sqrt(cpu) (the error at 1 CPU second by the 1/sqrt(t) law;
lower wins), and its ratio to pt's (pt/x > 1: x wins at equal CPU, x2 = >= 2x lower error)."""
import glob, json, math, os, subprocess, sys
from collections import defaultdict

vbl, refdir, outs = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = []
for out in outs:
    for cmd in sorted(glob.glob(os.path.join(out, "*.exr.cmd"))):
        img = cmd[:-4]
        sc, name, passes, seed = open(cmd).read().split()[:4]
        ref = os.path.join(refdir, sc + ".exr")
        if not (os.path.exists(img) and os.path.exists(ref) and os.path.exists(img + ".time")):
            continue
        u, s = open(img + ".time").read().split()[-2:]
        cpu = float(u) + float(s)
        j = json.loads(subprocess.run([vbl, "diff", img, ref, "--json"], capture_output=True, text=True).stdout)
        a = {l["name"]: l["rmae"] for l in j["layers"]}
        rows.append((sc, name, int(seed), int(passes), cpu, a[""], a.get("volume_from_volume", math.nan),
                     a.get("volume_direct", math.nan)))
print("# per render: scene config seed passes cpu_s beauty vfv vd (rMAE)")
for r in rows:
    print("%-12s %-9s %3d %4d %6.2f %.4f %.4f %.4f" % r)
agg = defaultdict(list)
for r in rows:
    agg[(r[0], r[1])].append(r)
print("\n# per scene and config, mean over seeds: cpu_s, rMAE x sqrt(cpu) (beauty, vfv, vd) +- spread (min-max), pt / config")
print("%-12s %-9s %2s %6s %16s %16s %16s %7s %7s %7s" % ("scene", "config", "n", "cpu", "beauty", "vfv", "vd", "pt/x b", "pt/x vfv", "pt/x vd"))
for sc in sorted({k[0] for k in agg}):
    base = agg.get((sc, "pt"))
    def eff(rs, i):
        v = [r[i] * math.sqrt(r[4]) for r in rs]
        return sum(v) / len(v), min(v), max(v)
    for (s2, name), rs in sorted(agg.items(), key=lambda kv: (kv[0][1] != "pt", kv[0][1])):
        if s2 != sc: continue
        e = [eff(rs, i) for i in (5, 6, 7)]
        ratios = []
        for k, i in enumerate((5, 6, 7)):
            ratios.append(eff(base, i)[0] / e[k][0] if base and e[k][0] > 0 else math.nan)
        cpu = sum(r[4] for r in rs) / len(rs)
        print("%-12s %-9s %2d %6.2f %s %s %s %7.2f %7.2f %7.2f" % (sc, name, len(rs), cpu,
              *("%6.3f (%.2f-%.2f)" % x for x in e), *ratios))
