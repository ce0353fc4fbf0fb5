#!/usr/bin/env python3
"""Issue 14: pt options A/B at equal CPU (each of the issue's items measured on its own).

For each scene: a reference from two independent long pt renders, the first with the first
configuration and the second with the last (their mean ratio per layer also checks that the two
estimators agree), then, interleaved (scene, seed, configuration), short single-thread renders
whose CPU time (user + system of the child) is measured. Per layer, rMAE = sum |img - ref| /
sum |ref| (as the Cycles race) and, at equal CPU, rMAE * sqrt(t / t_0), t_0 the first
configuration's mean CPU (the 1/sqrt(t) law). Not in CI (it measures time). Needs build/bin/vbl,
build/samples/cloud.vdb and Debian's python3 with python3-openimageio and numpy.

usage: /usr/bin/python3 bench/pt_ab/run.py --configs 'off=;split=--pt-camera-split true'
         [--out FILE] [--seeds 3] [--passes 8] [--ref-passes 128] [--res 48]
         [--scenes race_cloud,race_cloud_dense,race_cloud_ground,race_room]
"""
import argparse, os, shlex, subprocess, sys, time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from renders import LAYERS, ROOT, layers, render, rmae  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--configs", required=True, help="label=flags;label=flags (the first is the baseline)")
    ap.add_argument("--out")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--passes", type=int, default=8)
    ap.add_argument("--ref-passes", type=int, default=128)
    ap.add_argument("--res", type=int, default=48)
    ap.add_argument("--scenes", default="race_cloud,race_cloud_dense,race_cloud_ground,race_room")
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "pt_ab"))
    a = ap.parse_args()
    configs = []
    for item in a.configs.split(";"):
        label, _, flags = item.partition("=")
        configs.append((label.strip(), shlex.split(flags)))
    os.makedirs(a.work, exist_ok=True)
    res = ["--resolution", f"{a.res}x{a.res}"]
    lines = []

    def log(s=""):
        print(s, flush=True)
        lines.append(s)

    rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    log(f"# pt A/B (issue 14), {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {rev} (+ working tree)")
    log("# configs: " + "; ".join(f"{l} = {' '.join(f) or '(defaults)'}" for l, f in configs))
    log(f"# {a.res}x{a.res}, {a.passes} passes x the scene's spp per run, 1 thread, seeds 1..{a.seeds}; "
        f"references {a.ref_passes} passes x 2 ({configs[0][0]} and {configs[-1][0]}), 2 threads")
    log(f"# load average at start: {os.getloadavg()[0]:.1f} {os.getloadavg()[1]:.1f} {os.getloadavg()[2]:.1f} (2 cores)")
    log(f"# rMAE = sum|img - ref| / sum|ref|; at equal CPU: rMAE * sqrt(cpu / cpu({configs[0][0]})); "
        "floor = sum|h1-h2| / (2 sum|ref|)")
    for name in a.scenes.split(","):
        scene = os.path.join(ROOT, "bench", "scenes", f"{name}.json")
        h = []
        for i, (label, flags) in enumerate((configs[0], configs[-1])):
            p = os.path.join(a.work, f"{name}_ref{i}.exr")
            render(scene, p, res + flags + ["--passes", str(a.ref_passes), "--threads", "2", "--seed", str(1000 + i)])
            h.append(layers(p))
        ref = {l: 0.5 * (h[0][l] + h[1][l]) for l in h[0]}
        names = [l for l in LAYERS if l in ref and np.abs(ref[l]).sum() > 0]
        log(f"\n## {name} ({os.path.relpath(scene, ROOT)})")
        log(f"reference halves ({configs[0][0]} / {configs[-1][0]}) mean ratio per layer: " +
            ", ".join(f"{l} {h[0][l].sum() / h[1][l].sum():.4f}" for l in names))
        log("floor: " + ", ".join(f"{l} {np.abs(h[0][l] - h[1][l]).sum() / (2 * np.abs(ref[l]).sum()):.4f}" for l in names))
        data = {label: [] for label, _ in configs}
        for seed in range(1, a.seeds + 1):
            for label, flags in configs:
                p = os.path.join(a.work, f"{name}_{label}_s{seed}.exr")
                cpu = render(scene, p, res + flags + ["--passes", str(a.passes), "--threads", "1", "--seed", str(seed)])
                img = layers(p)
                data[label].append((cpu, {l: rmae(img[l], ref[l]) for l in names}))
        cpu0 = np.mean([c for c, _ in data[configs[0][0]]])
        log(f"{'config':>10} {'cpu s':>7} " + " ".join(f"{l[:20]:>20}" for l in names) +
            f"   (rMAE at {configs[0][0]}'s CPU, mean of seeds)")
        for label, _ in configs:
            cpu = np.mean([c for c, _ in data[label]])
            cols = []
            for l in names:
                v = [r[l] * np.sqrt(c / cpu0) for c, r in data[label]]
                cols.append(f"{np.mean(v):>11.4f} +-{np.std(v) / np.sqrt(len(v)):.4f}")
            log(f"{label:>10} {cpu:>7.2f} " + " ".join(f"{c:>20}" for c in cols))
    log(f"\n# load average at end: {os.getloadavg()[0]:.1f}")
    if a.out:
        with open(a.out, "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
