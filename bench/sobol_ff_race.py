"""Issue 14 item 2 (helper sobolff): pt.sampler independent vs sobol (old pattern: pixel, light,
equiangular and direction pairs; new: plus the free flight's first depth and real/null decision,
the light pick and the roulette), per layer, at equal CPU, on the race scenes.

Three configurations per scene and seed, run interleaved: `ind` (OLD_DIR, independent), `sobol_old`
(OLD_DIR, sobol), `sobol_new` (NEW_DIR, sobol). (NEW_DIR's independent sampling is bit-identical to
OLD_DIR's, checked by the script on the first seed.) Two error measures per layer:
- rMAE (bench/race_cycles/score.py) against a pt reference made of two independent halves rendered
  with OLD_DIR's independent sampler (their floor is printed), and
- the relative RMSE from the spread across seeds: sqrt(mean over pixels of the seeds' sample
  variance) / mean |ref|, which needs no reference (the estimators are unbiased).
Both are moved to `ind`'s CPU time by the 1/sqrt(t) law (score.equal_time_rmae): the ratio to
`ind` is then the error ratio at equal CPU (below 1: better). CPU = user + system of the vbl
process, 1 thread.

With OLD_DIR == NEW_DIR (one build) only two configurations run, `ind` and `sobol`, and the table
gives sobol/ind at equal CPU with its seed spread (the two means' relative standard errors combined
in quadrature).

usage: /usr/bin/python3 bench/sobol_ff_race.py OLD_DIR NEW_DIR OUT_DIR [--resolution 64x64]
       [--seeds 6] [--spp 16,64] [--ref-spp 1024] [--ref-threads 2] [--scenes race_cloud,...]
"""
import argparse
import os
import resource
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "race_cycles"))
import numpy as np  # noqa: E402
import score  # noqa: E402

SCENES = ["race_cloud", "race_cloud_dense", "race_cloud_ground", "race_room"]
LAYERS = ["beauty", "surface_direct", "surface_from_surface", "surface_from_volume", "volume_direct",
          "volume_from_surface", "volume_from_volume"]


def run(bindir, scene, out, samples, seed, res, sampler, threads=1):
    spp = 4 if samples % 4 == 0 else 1
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [os.path.join(bindir, "vbl"), "render", scene, "--method", "pt", "--passes", str(samples // spp), "--spp",
           str(spp), "--seed", str(seed), "--resolution", res, "--threads", str(threads), "--pt-sampler", sampler,
           "-o", out]
    env = dict(os.environ, LD_LIBRARY_PATH=bindir)
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def print_two(layers, ref, floor, cpu, err, imgs, seeds):
    c_ind = float(np.mean(cpu["ind"]))
    print("| layer | ref floor | ind rMAE (+-se) | sobol rMAE (+-se) | sobol/ind rMAE at equal CPU | "
          "sobol/ind seed-spread RMSE at equal CPU |")
    print("|---|---|---|---|---|---|")
    for l in layers:
        mean_ref = float(np.abs(ref[l]).mean())
        m, at, rel, se = {}, {}, {}, {}
        for label in ("ind", "sobol"):
            e = np.array(err[label][l])
            m[label] = float(np.sqrt(max(np.mean(e) ** 2 - floor[l] ** 2, 0.0)))
            # relative standard error of the floor-corrected mean (d m / d mean(e) = mean(e) / m)
            se[label] = float(np.std(e, ddof=1) / np.sqrt(seeds) * np.mean(e) / max(m[label], 1e-30) ** 2)
            c = float(np.mean(cpu[label]))
            at[label] = score.equal_time_rmae(m[label], c, c_ind)
            var = np.var(np.stack(imgs[label][l]), axis=0, ddof=1)
            rel[label] = score.equal_time_rmae(float(np.sqrt(var.mean())) / mean_ref, c, c_ind)
        r = at["sobol"] / max(at["ind"], 1e-30)
        print(f"| {l} | {floor[l]:.4f} | {m['ind']:.4f} (+-{100 * se['ind']:.0f}%) | {m['sobol']:.4f} "
              f"(+-{100 * se['sobol']:.0f}%) | {r:.3f} +- {r * np.hypot(se['ind'], se['sobol']):.3f} | "
              f"{rel['sobol'] / max(rel['ind'], 1e-30):.3f} |")
    print("cpu s (mean over seeds): " + ", ".join(f"{k} {np.mean(v):.2f} (+-{np.std(v):.2f})"
                                                    for k, v in cpu.items()), flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("out")
    ap.add_argument("--resolution", default="64x64")
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--spp", default="16,64")
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--ref-threads", type=int, default=2)
    ap.add_argument("--scenes", default=",".join(SCENES))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")
    one = os.path.realpath(a.old) == os.path.realpath(a.new)
    configs = [("ind", a.old, "independent"), ("sobol_old", a.old, "sobol"), ("sobol_new", a.new, "sobol")]
    if one:
        configs = [("ind", a.old, "independent"), ("sobol", a.old, "sobol")]
    for name in a.scenes.split(","):
        scene = os.path.join(here, name + ".json")
        halves = []
        for k in range(2):
            out = os.path.join(a.out, f"{name}_ref{k}.exr")
            if not os.path.exists(out):
                run(a.old, scene, out, a.ref_spp, 1000 + k, a.resolution, "independent", a.ref_threads)
            halves.append(score.read_vbl_layers(out))
        ref = {l: 0.5 * (halves[0][l] + halves[1][l]) for l in halves[0]}
        layers = [l for l in LAYERS if l in ref and float(np.abs(ref[l]).sum()) > 0]
        floor = {l: score.floor_rmae(halves[0][l], halves[1][l]) for l in layers}
        for samples in [int(x) for x in a.spp.split(",")]:
            cpu = {c[0]: [] for c in configs}
            err = {c[0]: {l: [] for l in layers} for c in configs}
            imgs = {c[0]: {l: [] for l in layers} for c in configs}
            for seed in range(1, a.seeds + 1):
                for label, b, sampler in configs:
                    out = os.path.join(a.out, f"{name}_{samples}_{label}_{seed}.exr")
                    cpu[label].append(run(b, scene, out, samples, seed, a.resolution, sampler))
                    img = score.read_vbl_layers(out)
                    for l in layers:
                        err[label][l].append(score.rmae(img[l], ref[l]))
                        imgs[label][l].append(img[l])
                if seed == 1 and not one:
                    out = os.path.join(a.out, f"{name}_{samples}_ind_new_{seed}.exr")
                    run(a.new, scene, out, samples, seed, a.resolution, "independent")
                    same = all(np.array_equal(score.read_vbl_layers(out)[l], imgs["ind"][l][0]) for l in layers)
                    print(f"# {name} {samples} spp: new binary's independent sampling bit-identical to old: {same}")
            c_ind = float(np.mean(cpu["ind"]))
            print(f"\n## {name}, {a.resolution}, {samples} spp, {a.seeds} seeds, reference 2 x {a.ref_spp} spp")
            if one:
                print_two(layers, ref, floor, cpu, err, imgs, a.seeds)
                continue
            print("| layer | ref floor | ind rMAE | sobol_old rMAE | sobol_new rMAE | old/ind at equal CPU | "
                  "new/ind at equal CPU | new/old at equal CPU | RMSE new/ind at equal CPU | RMSE old/ind |")
            print("|---|---|---|---|---|---|---|---|---|---|")
            for l in layers:
                mean_ref = float(np.abs(ref[l]).mean())
                m, at, rel = {}, {}, {}
                for label, _, _ in configs:
                    e = np.array(err[label][l])
                    # the reference's floor removed in quadrature (independent errors)
                    m[label] = float(np.sqrt(max(np.mean(e) ** 2 - floor[l] ** 2, 0.0)))
                    c = float(np.mean(cpu[label]))
                    at[label] = score.equal_time_rmae(m[label], c, c_ind)
                    var = np.var(np.stack(imgs[label][l]), axis=0, ddof=1)
                    rel[label] = score.equal_time_rmae(float(np.sqrt(var.mean())) / mean_ref, c, c_ind)
                spread = float(np.std(err["ind"][l], ddof=1) / np.sqrt(a.seeds) / max(np.mean(err["ind"][l]), 1e-30))
                print(f"| {l} | {floor[l]:.4f} | {m['ind']:.4f} (+-{100 * spread:.0f}%) | {m['sobol_old']:.4f} | "
                      f"{m['sobol_new']:.4f} | {at['sobol_old'] / at['ind']:.3f} | {at['sobol_new'] / at['ind']:.3f} | "
                      f"{at['sobol_new'] / at['sobol_old']:.3f} | {rel['sobol_new'] / rel['ind']:.3f} | "
                      f"{rel['sobol_old'] / rel['ind']:.3f} |")
            print("cpu s (mean over seeds): " + ", ".join(f"{k} {np.mean(v):.2f} (+-{np.std(v):.2f})"
                                                            for k, v in cpu.items()), flush=True)


if __name__ == "__main__":
    main()
