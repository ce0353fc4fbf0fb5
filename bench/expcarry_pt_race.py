"""Issue 14 item 5 (helper expcarry): pt end to end, old vs new tracking core side by side.
Beauty rMAE (bench/race_cycles/score.py) against a long pt reference made of two halves, one
rendered by each binary (their rMAE floor doubles as an old-vs-new bias check), at equal CPU:
each run's rMAE is moved to the old run's CPU time of the same seed by the 1/sqrt(t) law
(score.equal_time_rmae). CPU time = user + system of the vbl process, 1 thread; old and new run
interleaved per scene and seed.

usage: /usr/bin/python3 bench/expcarry_pt_race.py OLD_DIR NEW_DIR OUT_DIR [--resolution 64x48]
  OLD_DIR / NEW_DIR hold vbl and libvbl.so.0 (run with LD_LIBRARY_PATH=DIR).
"""
import argparse
import os
import resource
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "race_cycles"))
import numpy as np  # noqa: E402
import score  # noqa: E402

SCENES = ["race_cloud", "race_cloud_dense", "race_room"]


def run(bindir, scene, out, passes, seed, res):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [os.path.join(bindir, "vbl"), "render", scene, "--method", "pt", "--passes", str(passes), "--spp", "4",
           "--seed", str(seed), "--resolution", res, "--threads", "1", "-o", out]
    env = dict(os.environ, LD_LIBRARY_PATH=bindir)
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("out")
    ap.add_argument("--resolution", default="64x48")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--passes", type=int, default=4)
    ap.add_argument("--ref-passes", type=int, default=64)
    ap.add_argument("--scenes", default=",".join(SCENES))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")
    print("| scene | seed | old CPU s | new CPU s | new/old CPU | old rMAE | new rMAE | new rMAE at old CPU | "
          "efficiency new/old |\n|---|---|---|---|---|---|---|---|---|", flush=True)
    summary = []
    for name in a.scenes.split(","):
        scene = os.path.join(here, name + ".json")
        halves = []
        for k, b in enumerate((a.old, a.new)):
            out = os.path.join(a.out, f"{name}_ref{k}.exr")
            run(b, scene, out, a.ref_passes, 1000 + k, a.resolution)
            halves.append(score.read_vbl_layers(out)["beauty"])
        ref = 0.5 * (halves[0] + halves[1])
        floor = score.floor_rmae(halves[0], halves[1])
        effs = []
        for seed in range(1, a.seeds + 1):
            cpu, err = {}, {}
            for label, b in (("old", a.old), ("new", a.new)):
                out = os.path.join(a.out, f"{name}_{label}_{seed}.exr")
                cpu[label] = run(b, scene, out, a.passes, seed, a.resolution)
                err[label] = score.rmae(score.read_vbl_layers(out)["beauty"], ref)
            at = score.equal_time_rmae(err["new"], cpu["new"], cpu["old"])
            eff = (err["old"] / at) ** 2  # = (err_old^2 cpu_old) / (err_new^2 cpu_new)
            effs.append(eff)
            print(f"| {name} | {seed} | {cpu['old']:.2f} | {cpu['new']:.2f} | {cpu['new'] / cpu['old']:.3f} | "
                  f"{err['old']:.4f} | {err['new']:.4f} | {at:.4f} | {eff:.3f} |", flush=True)
        summary.append((name, floor, float(np.exp(np.mean(np.log(effs))))))
    print("\n| scene | reference floor rMAE (old half vs new half) | efficiency new/old (geometric mean over seeds) |"
          "\n|---|---|---|")
    for name, floor, eff in summary:
        print(f"| {name} | {floor:.4f} | {eff:.3f} |")


if __name__ == "__main__":
    main()
