"""The quality presets against the alternatives (issue #13 item 7), on the race's scenes and
references: bench/race_cycles/run.sh --presets [--scenes ...] [--final-scenes ...].

Per scene: `vbl render --preset preview` (2 threads), its CPU time t_p and its error per layer
against the race's pt reference (the newest cached one under BUILD/race_cycles; run the race
first); then every other method with its defaults given t_p (race.Race.method_at_budget): the
fastest good-looking image at seconds. The same for `--preset final` on --final-scenes (minutes
each: the fastest to a low unbiased error). Writes bench/results/race_presets.{csv,txt}.
"""
import argparse
import csv
import glob
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import race  # noqa: E402
import score  # noqa: E402


def cached_reference(work, name):
    firsts = sorted(glob.glob(os.path.join(work, f"{name}_ref_*_0.exr")), key=os.path.getmtime)
    if not firsts:
        sys.exit(f"race_presets: no cached reference for {name} under {work}: run bench/race_cycles/run.sh first")
    h = [score.read_vbl_layers(firsts[-1]), score.read_vbl_layers(firsts[-1][:-6] + "_1.exr")]
    return {k: 0.5 * (h[0][k] + h[1][k]) for k in h[0]}, h


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(race.ROOT, "build"))
    ap.add_argument("--scenes", default="cloud,cloud_dense,room")
    ap.add_argument("--final-scenes", default="cloud")
    ap.add_argument("--methods", default="vrl,vbl,vpl,beams")
    ap.add_argument("--out", default=os.path.join(race.ROOT, "bench", "results", "race_presets"))
    a = ap.parse_args()
    a.work = os.path.join(a.build, "race_cycles")
    a.method_args = {}
    r = race.Race(a)
    rows = []
    jobs = [(s, "preview") for s in a.scenes.split(",")] + [(s, "final") for s in a.final_scenes.split(",") if s]
    for name, preset in jobs:
        scene = os.path.join(race.ROOT, "bench", "scenes", f"race_{name}.json")
        ref, halves = cached_reference(a.work, name)
        surfaces = "surface_direct" in ref and float(ref["surface_direct"].sum()) > 0
        out = os.path.join(a.work, f"{name}_preset_{preset}.exr")
        r.log(f"{name}: --preset {preset}")
        cpu, wall = race.timed([r.vbl, "render", scene, "-o", out, "--vdb", r.vdb, "--preset", preset,
                                "--threads", "2"], out + ".log")
        runs = [(f"preset {preset} (pt)", out, cpu, wall, "-")]
        for m in a.methods.split(","):
            if (m == "beams" and surfaces) or (m == "vpl" and not surfaces):
                continue
            r.log(f"{name}: {m} at {cpu:.1f} CPU s")
            o, c, w, p = r.method_at_budget(scene, f"{name}_{preset}", m, cpu)
            runs.append((m, o, c, w, p))
        for label, path, c, w, p in runs:
            layers = score.read_vbl_layers(path)
            for k in score.VBL_LAYERS:
                if k not in ref or float(ref[k].sum()) <= 0:
                    continue
                raw = score.rmae(layers[k], ref[k])
                rows.append(dict(scene=name, preset=preset, config=label, layer=k, passes=p, cpu_s=c, wall_s=w,
                                 budget_s=cpu, rmae=raw, rmae_at_budget=score.equal_time_rmae(raw, c, cpu),
                                 energy=score.energy(layers[k], ref[k]), fireflies=score.fireflies(layers[k], ref[k]),
                                 ref_floor=score.floor_rmae(halves[0][k], halves[1][k])))
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    text = ["# Presets against the alternatives at the preset's CPU time (bench/race_cycles/run.sh --presets)", "",
            "rMAE against the race's pt reference (sum|img - ref| / sum|ref|), moved to the preset's CPU time by 1/sqrt(t) "
            "where a run missed it; load average: " + "/".join(open("/proc/loadavg").read().split()[:3]), "",
            "| scene | preset | config | passes | CPU s | beauty rMAE | volume_from_volume rMAE | energy (beauty) | fireflies |",
            "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    for row in rows:
        if row["layer"] != "beauty":
            continue
        v = [x for x in rows if x["scene"] == row["scene"] and x["preset"] == row["preset"] and
             x["config"] == row["config"] and x["layer"] == "volume_from_volume"]
        text.append(f"| {row['scene']} | {row['preset']} | {row['config']} | {row['passes']} | {row['cpu_s']:.1f} | "
                    f"{row['rmae_at_budget']:.4f} | {v[0]['rmae_at_budget'] if v else float('nan'):.4f} | "
                    f"{row['energy']:.3f} | {row['fireflies']} |")
    open(a.out + ".txt", "w").write("\n".join(text) + "\n")
    print("\n".join(text))


if __name__ == "__main__":
    main()
