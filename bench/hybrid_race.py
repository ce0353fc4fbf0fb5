"""render.hybrid (issue #13 item 6) side by side: pt, vrl, and vrl / vbl / vpl with --hybrid auto
on bench/scenes race_room, race_cloud and race_spot_smoke, per-layer rMAE (bench/race_cycles/
score.py: sum |img - ref| / sum |ref|) against a long pt reference made of two independent halves
(their floor is reported), at equal CPU time: each run's rMAE is moved to the budget (the pt run's
CPU time of the same seed) by the 1/sqrt(t) law (score.equal_time_rmae). CPU time = user + system
of the vbl process (pilot included). Interleaved: per scene and seed every configuration runs
once, in the same order, so load changes hit all of them alike.

usage: /usr/bin/python3 bench/hybrid_race.py BUILD_BIN_VBL OUT_DIR [--resolution 32x32] [--seeds 2]
       [--scenes race_room,...] [--configs pt,vrl,vrl+auto,vbl,vbl+auto,vpl+auto]
"""
import argparse
import json
import os
import resource
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "race_cycles"))
import numpy as np  # noqa: E402
import score  # noqa: E402

SCENES = ["race_room", "race_cloud", "race_spot_smoke"]
LAYERS = ["beauty", "surface_direct", "surface_from_surface", "surface_from_volume", "volume_direct",
          "volume_from_volume"]
# (label, method, passes, extra flags)
ALL_CONFIGS = [("pt", "pt", 32, []), ("vrl", "vrl", 4, []), ("vrl+auto", "vrl", 16, ["--hybrid", "auto"]),
               ("vbl", "vbl", 4, []), ("vbl+auto", "vbl", 16, ["--hybrid", "auto"]),
               ("vpl+auto", "vpl", 1, ["--hybrid", "auto"])]
CONFIGS = ALL_CONFIGS


def run(vbl, scene, out, method, passes, seed, res, extra):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [vbl, "render", scene, "--method", method, "--passes", str(passes), "--seed", str(seed),
           "--resolution", res, "--threads", "1", "-o", out] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr)
    note = [ln for ln in p.stderr.splitlines() if "hybrid:" in ln]
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, (note[0].split("hybrid: ", 1)[1] if note else "")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("vbl")
    ap.add_argument("out")
    ap.add_argument("--resolution", default="32x32")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--ref-passes", type=int, default=64)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--configs", default="pt,vrl,vrl+auto,vbl+auto,vpl+auto",
                    help="labels of ALL_CONFIGS, the first is the budget (pt)")
    ap.add_argument("--report-from", help="rows.json of an earlier run: print its tables, render nothing")
    a = ap.parse_args()
    global CONFIGS
    CONFIGS = [c for label in a.configs.split(",") for c in ALL_CONFIGS if c[0] == label]
    if a.report_from:
        with open(a.report_from) as f:
            report(json.load(f), a.scenes.split(","))
        return
    os.makedirs(a.out, exist_ok=True)
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")
    rows = []
    for name in a.scenes.split(","):
        scene = os.path.join(here, name + ".json")
        halves, ref_cpu = [], 0.0
        for k in (0, 1):
            out = os.path.join(a.out, f"{name}_ref{k}.exr")
            cpu, _ = run(a.vbl, scene, out, "pt", a.ref_passes, 1000 + k, a.resolution, [])
            ref_cpu += cpu
            halves.append(score.read_vbl_layers(out))
        ref = {k: 0.5 * (halves[0][k] + halves[1][k]) for k in halves[0]}
        floor = {k: score.floor_rmae(halves[0][k], halves[1][k]) for k in ref}
        print(f"{name}: reference {2 * a.ref_passes} pt passes, {ref_cpu:.1f} CPU s", flush=True)
        for seed in range(1, a.seeds + 1):
            budget = None
            for label, method, passes, extra in CONFIGS:
                out = os.path.join(a.out, f"{name}_{label}_{seed}.exr")
                cpu, plan = run(a.vbl, scene, out, method, passes, seed, a.resolution, extra)
                if budget is None:
                    budget = cpu
                img = score.read_vbl_layers(out)
                for layer in LAYERS:
                    if layer not in ref or layer not in img or not np.any(ref[layer]):
                        continue
                    raw = score.rmae(img[layer], ref[layer])
                    rows.append(dict(scene=name, config=label, seed=seed, layer=layer, cpu_s=cpu, budget_s=budget,
                                     rmae=raw, rmae_at_budget=score.equal_time_rmae(raw, cpu, budget),
                                     floor=floor[layer], plan=plan))
                print(f"  seed {seed} {label:9s} {cpu:6.2f} CPU s  beauty rMAE "
                      f"{[r['rmae_at_budget'] for r in rows if r['config'] == label and r['layer'] == 'beauty' and r['scene'] == name][-1]:.4f}"
                      f"  {plan}", flush=True)
    with open(os.path.join(a.out, "rows.json"), "w") as f:
        json.dump(rows, f, indent=1)
    report(rows, a.scenes.split(","))


def floor_out_at_budget(r):
    """rMAE at the budget with the reference's floor taken out before the 1/sqrt(t) move: a run's
    raw error sqrt(e^2 - floor^2) is its own; moving the floor too would charge long runs for the
    reference's noise."""
    own = np.sqrt(max(r["rmae"] ** 2 - r["floor"] ** 2, 0.0))
    return score.equal_time_rmae(own, r["cpu_s"], r["budget_s"])


def report(rows, scenes):
    # table: mean over seeds of the equal-CPU rMAE per scene, layer, config
    print("\nequal-CPU rMAE (mean over seeds; budget = the pt run's CPU s), reference floor in ()")
    for name in scenes:
        layers = [l for l in LAYERS if any(r["scene"] == name and r["layer"] == l for r in rows)]
        print(f"\n{name}")
        print(f"{'layer':22s}" + "".join(f"{c[0]:>11s}" for c in CONFIGS) + "   floor")
        for l in layers:
            line = f"{l:22s}"
            for c in CONFIGS:
                v = [r["rmae_at_budget"] for r in rows if r["scene"] == name and r["layer"] == l and r["config"] == c[0]]
                line += f"{np.mean(v):11.4f}" if v else f"{'-':>11s}"
            fl = [r["floor"] for r in rows if r["scene"] == name and r["layer"] == l]
            print(line + f"   ({fl[0]:.4f})")
        cpus = {c[0]: np.mean([r["cpu_s"] for r in rows if r["scene"] == name and r["config"] == c[0]]) for c in CONFIGS}
        print("CPU s per run: " + ", ".join(f"{k} {v:.2f}" for k, v in cpus.items()))
        line = f"{'beauty, floor out':22s}"
        for c in CONFIGS:
            v = [floor_out_at_budget(r) for r in rows if r["scene"] == name and r["layer"] == "beauty" and r["config"] == c[0]]
            line += f"{np.mean(v):11.4f}" if v else f"{'-':>11s}"
        print(line)
        plans = sorted({(r["config"], r["plan"]) for r in rows if r["scene"] == name and r["plan"]})
        for cfg, plan in plans:
            print(f"  {cfg}: {plan}")


if __name__ == "__main__":
    main()
