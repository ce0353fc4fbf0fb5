#!/usr/bin/env python3
"""Issue 14: pt.direct_strata (stratified single scattering along camera rays) at equal CPU.

For each scene: a reference from two independent long pt renders (one at K = 1, one at the
largest K, so their difference also checks that the estimators agree), then, interleaved
(scene-major, seed, K), short single-thread renders whose CPU time (user + system of the child)
is measured. Per layer, rMAE = sum |img - ref| / sum |ref| (as bench_curves and the Cycles
race) and, at equal CPU, rMAE * sqrt(t / t_1) with t_1 the mean CPU of K = 1 (the 1/sqrt(t) law).
Not in CI (it measures time). Needs build/bin/vbl, build/samples/cloud.vdb and Debian's python3
with python3-openimageio and numpy.

usage: /usr/bin/python3 bench/pt_direct_strata/run.py [--out FILE] [--seeds 3] [--passes 8]
         [--ref-passes 192] [--res 64] [--ks 1,2,4,8] [--scenes cloud,cloud_dense,room]
"""
import argparse, os, subprocess, sys, time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pt_ab"))
from renders import ROOT, layers, render, rmae  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "pt_direct_strata_issue14.txt"))
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--passes", type=int, default=8)
    ap.add_argument("--ref-passes", type=int, default=192)
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--ks", default="1,2,4,8")
    ap.add_argument("--scenes", default="cloud,cloud_dense,room,room_noeq")
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "pt_direct_strata"))
    a = ap.parse_args()
    ks = [int(k) for k in a.ks.split(",")]
    os.makedirs(a.work, exist_ok=True)
    res = ["--resolution", f"{a.res}x{a.res}"]
    lines = []

    def log(s=""):
        print(s, flush=True)
        lines.append(s)

    log(f"# pt.direct_strata (issue 14), {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    log(f"# commit {rev}; {a.res}x{a.res}, {a.passes} passes x the scene's spp per run, 1 thread, seeds 1..{a.seeds}; "
        f"references {a.ref_passes} passes x 2 (K=1 and K={ks[-1]}), 2 threads")
    log(f"# load average at start: {os.getloadavg()[0]:.1f} {os.getloadavg()[1]:.1f} {os.getloadavg()[2]:.1f} (2 cores)")
    log("# rMAE = sum|img - ref| / sum|ref|; at equal CPU: rMAE * sqrt(cpu / cpu(K=1)); floor = sum|h1-h2| / (2 sum|ref|)")
    for name in a.scenes.split(","):
        base = name.replace("_noeq", "")
        scene = os.path.join(ROOT, "bench", "scenes", f"race_{base}.json")
        sextra = ["--pt-equiangular", "false"] if name.endswith("_noeq") else []
        h = []
        for i, k in enumerate((ks[0], ks[-1])):
            p = os.path.join(a.work, f"{name}_ref{i}.exr")
            render(scene, p, res + sextra + ["--passes", str(a.ref_passes), "--threads", "2", "--seed", str(1000 + i),
                                               "--pt-direct-strata", str(k)])
            h.append(layers(p))
        ref = {l: 0.5 * (h[0][l] + h[1][l]) for l in h[0]}
        names = [l for l in ("beauty", "volume_direct", "volume_from_volume", "surface_direct", "surface_from_volume",
                             "volume_from_surface", "surface_from_surface") if l in ref and np.abs(ref[l]).sum() > 0]
        log(f"\n## {name} ({os.path.relpath(scene, ROOT)}{' --pt-equiangular false' if sextra else ''})")
        log("reference halves (K=%d / K=%d) mean ratio per layer: " % (ks[0], ks[-1]) +
            ", ".join(f"{l} {h[0][l].sum() / h[1][l].sum():.4f}" for l in names))
        log("floor: " + ", ".join(f"{l} {np.abs(h[0][l] - h[1][l]).sum() / (2 * np.abs(ref[l]).sum()):.4f}" for l in names))
        data = {k: [] for k in ks}
        for seed in range(1, a.seeds + 1):
            for k in ks:
                p = os.path.join(a.work, f"{name}_k{k}_s{seed}.exr")
                cpu = render(scene, p, res + sextra + ["--passes", str(a.passes), "--threads", "1", "--seed", str(seed),
                                                       "--pt-direct-strata", str(k)])
                img = layers(p)
                data[k].append((cpu, {l: rmae(img[l], ref[l]) for l in names}))
        cpu1 = np.mean([c for c, _ in data[ks[0]]])
        log(f"{'K':>3} {'cpu s':>7} " + " ".join(f"{l:>20}" for l in names) + "   (rMAE at K=1's CPU, mean of seeds)")
        for k in ks:
            cpu = np.mean([c for c, _ in data[k]])
            cols = []
            for l in names:
                v = [r[l] * np.sqrt(c / cpu1) for c, r in data[k]]
                cols.append(f"{np.mean(v):>12.4f} +-{np.std(v) / np.sqrt(len(v)):.4f}")
            log(f"{k:>3} {cpu:>7.2f} " + " ".join(f"{c:>20}" for c in cols))
    log(f"\n# load average at end: {os.getloadavg()[0]:.1f}")
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
