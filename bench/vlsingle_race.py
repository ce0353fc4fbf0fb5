"""The virtual lights' single scattering (issue 13; docs/readme/vrl.md) before / after, side by side:
vrl, vbl and vpl with the old binary (OLD_VBL, its libvbl.so beside it) and the new one (NEW_VBL)
on bench/scenes race_room, race_spot_smoke, race_cloud and race_cloud_ground, plus pt (new), per
layer rMAE (bench/race_cycles/score.py: sum |img - ref| / sum |ref|) against a long pt reference
made of two independent halves (their floor is reported). CPU time = user + system of the vbl
process (getrusage of the children). Interleaved: per scene and seed every configuration runs
once, old and new of a method next to each other, the order of the pair alternating with the
seed (ABBA), so load changes hit both alike. Efficiency at equal CPU: rMAE * sqrt(cpu / cpu_old).

usage: /usr/bin/python3 bench/vlsingle_race.py OLD_VBL NEW_VBL OUT_DIR [--resolution 64x64]
       [--seeds 2] [--passes 16] [--ref-passes 128] [--scenes room,spot_smoke,...]
A rerun on the same OUT_DIR skips the renders listed in OUT_DIR/cpu.json (and the references
there), so a run can be split over processes and the report made from their merged outputs.
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

score.VBL_LAYERS = score.VBL_LAYERS + ["background", "volume_emission"]
SCENES = ["room", "spot_smoke", "cloud", "cloud_ground"]
LAYERS = ["volume_direct", "background", "beauty"]
# (method, extra flags): vpl with 200 light paths (its default pass is minutes long)
METHODS = [("vrl", []), ("vbl", []), ("vpl", ["--light-paths", "200"])]


def run(vbl, scene, out, method, passes, seed, res, extra):
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = os.path.dirname(os.path.abspath(vbl))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [vbl, "render", scene, "--method", method, "--passes", str(passes), "--spp", "1", "--seed", str(seed),
           "--resolution", res, "--threads", "1", "-o", out] + extra
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
    ap.add_argument("--resolution", default="64x64")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--passes", type=int, default=16)
    ap.add_argument("--ref-passes", type=int, default=128)
    ap.add_argument("--scenes", default=",".join(SCENES))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")
    rows = []
    cpu_path = os.path.join(a.out, "cpu.json")  # {exr name: CPU s}: a rerun skips what it holds
    cpus = json.load(open(cpu_path)) if os.path.exists(cpu_path) else {}
    for name in a.scenes.split(","):
        scene = os.path.join(here, f"race_{name}.json")
        halves = []
        for k in (0, 1):
            out = os.path.join(a.out, f"{name}_ref{k}.exr")
            if not os.path.exists(out):
                env = dict(os.environ, LD_LIBRARY_PATH=os.path.dirname(os.path.abspath(a.new)))
                subprocess.run([a.new, "render", scene, "--method", "pt", "--passes", str(a.ref_passes), "--spp", "4",
                                "--seed", str(1000 + k), "--resolution", a.resolution, "--threads", "1", "-o", out],
                               check=True, capture_output=True, env=env)
            halves.append(score.read_vbl_layers(out))
        ref = {k: 0.5 * (halves[0][k] + halves[1][k]) for k in halves[0]}
        floor = {k: score.floor_rmae(halves[0][k], halves[1][k]) for k in ref}
        for seed in range(1, a.seeds + 1):
            configs = [("pt", a.new, "pt", [])]
            for method, extra in METHODS:
                pair = [("old", a.old), ("new", a.new)]
                if seed % 2 == 0:
                    pair.reverse()
                configs += [(f"{method} {tag}", b, method, extra) for tag, b in pair]
            for label, binary, method, extra in configs:
                out = os.path.join(a.out, f"{name}_{label.replace(' ', '_')}_{seed}.exr")
                key = os.path.basename(out)
                if key in cpus and os.path.exists(out):  # resumed: rendered before, its CPU time kept
                    cpu = cpus[key]
                else:
                    cpu = run(binary, scene, out, method, a.passes, seed, a.resolution, extra)
                    cpus[key] = cpu
                    with open(cpu_path, "w") as f:
                        json.dump(cpus, f, indent=1)
                img = score.read_vbl_layers(out)
                for layer in LAYERS:
                    if layer not in ref or layer not in img or not np.any(ref[layer]):
                        continue
                    rows.append(dict(scene=name, config=label, seed=seed, layer=layer, cpu_s=cpu,
                                     rmae=score.rmae(img[layer], ref[layer]), floor=floor[layer]))
                print(f"  {name} seed {seed} {label:8s} {cpu:6.2f} CPU s", flush=True)
    with open(os.path.join(a.out, "rows.json"), "w") as f:
        json.dump(rows, f, indent=1)

    def get(name, label, layer, key):
        return [r[key] for r in sorted(rows, key=lambda r: r["seed"])
                if r["scene"] == name and r["config"] == label and r["layer"] == layer]

    print(f"\n{a.resolution}, {a.passes} passes x 1 spp, seeds 1..{a.seeds}, 1 thread; reference 2 x {a.ref_passes} x 4 spp pt")
    print("rMAE per layer (mean over seeds), CPU s per run, new/old ratios per seed: rMAE, CPU, "
          "efficiency rMAE*sqrt(cpu) (< 1: new better)")
    for name in a.scenes.split(","):
        print(f"\nrace_{name}  (reference floor: " +
              ", ".join(f"{l} {get(name, 'pt', l, 'floor')[0]:.4f}" for l in LAYERS if get(name, 'pt', l, 'floor')) + ")")
        print(f"  pt: CPU {np.mean(get(name, 'pt', 'beauty', 'cpu_s')):.2f} s, " +
              ", ".join(f"{l} {np.mean(get(name, 'pt', l, 'rmae')):.4f}" for l in LAYERS if get(name, 'pt', l, 'rmae')))
        for method, _ in METHODS:
            co = np.array(get(name, f"{method} old", "beauty", "cpu_s"))
            cn = np.array(get(name, f"{method} new", "beauty", "cpu_s"))
            print(f"  {method}: CPU old {co.mean():.2f} s new {cn.mean():.2f} s, ratio " +
                  " ".join(f"{x:.3f}" for x in cn / co))
            for l in LAYERS:
                ro, rn = np.array(get(name, f"{method} old", l, "rmae")), np.array(get(name, f"{method} new", l, "rmae"))
                if len(ro) == 0:
                    continue
                eff = rn * np.sqrt(cn) / (ro * np.sqrt(co))
                print(f"    {l:14s} old {ro.mean():.4f} new {rn.mean():.4f}  rMAE ratio " +
                      " ".join(f"{x:.3f}" for x in rn / ro) + "  efficiency ratio " +
                      " ".join(f"{x:.3f}" for x in eff))


if __name__ == "__main__":
    main()
