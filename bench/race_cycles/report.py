"""Tables, CSV and plot of the Cycles race (bench/race_cycles/race.py)."""
import argparse
import csv
import json
import math
import os
import platform
import subprocess
import time

import score

PT14_TARGET = 0.45   # issue #14: pt's error <= 0.45x Cycles' on every layer at equal time
RMAE13 = 0.1         # issue #13: medium rMAE 0.1 within 3x pt's time
ENERGY13 = 0.97      # issue #13: vbl energy >= 0.97


def _f(x, fmt="%.4f"):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else fmt % x


def _rows(race, **kw):
    return [r for r in race.rows if all(r[k] == v for k, v in kw.items())]


def _one(race, **kw):
    rows = _rows(race, **kw)
    return rows[0] if rows else None


def corrected(e, floor):
    """rMAE with the reference's own noise taken out: sqrt(e^2 - floor^2) (independent noise)."""
    return math.sqrt(max(e * e - floor * floor, 0.0)) if not math.isnan(floor) else e


def table14(race):
    out = ["## Issue #14: Cycles vs pt at Cycles' CPU time (rMAE against the pt reference; ratio = pt / Cycles, target <= %.2f)" % PT14_TARGET, "",
           "The last ratio takes the reference's own noise out of both errors: sqrt(rMAE^2 - floor^2).", "",
           "| scene | layer | Cycles rMAE | pt rMAE | pt / Cycles | target | ref floor | pt / Cycles, floor out |",
           "|---|---|---:|---:|---:|---|---:|---:|"]
    for scene in race.a.scenes:
        for r in _rows(race, scene=scene, method="cycles", layers="cycles"):
            p = _one(race, scene=scene, method="pt", layers="cycles", layer=r["layer"])
            ratio = p["rmae_at_budget"] / r["rmae"] if r["rmae"] > 0 else float("nan")
            fl = r["ref_floor"]
            cc, cp = corrected(r["rmae"], fl), corrected(p["rmae_at_budget"], fl)
            out.append(f"| {scene} | {r['layer']} | {_f(r['rmae'])} | {_f(p['rmae_at_budget'])} | {_f(ratio, '%.2f')} | "
                       f"{'met' if ratio <= PT14_TARGET else 'not met'} | {_f(fl)} | {_f(cp / cc if cc > 0 else float('nan'), '%.2f')} |")
    return out


def table13(race):
    out = ["## Issue #13: every method at the same CPU time (rMAE against the pt reference)", "",
           "t(0.1) / t_pt(0.1): CPU time to medium (beauty) rMAE 0.1 by the 1/sqrt(t) law, over pt's (target <= 3); "
           "energy = layer sum / reference (target >= %.2f for vbl); fireflies = pixels above 10x the reference, minus pt's." % ENERGY13, "",
           "| scene | method | passes | CPU s | beauty rMAE | volume_from_volume rMAE | vfv pt / method | t(0.1) / t_pt(0.1) | energy (beauty) | energy (vfv) | fireflies beyond pt |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for scene in race.a.scenes:
        ptb = _one(race, scene=scene, method="pt", layers="vbl", layer="beauty")
        ptv = _one(race, scene=scene, method="pt", layers="vbl", layer="volume_from_volume")
        if ptb is None:
            continue
        t_pt = score.time_to_rmae(ptb["rmae_at_budget"], ptb["budget_s"], RMAE13)
        for b in _rows(race, scene=scene, layers="vbl", layer="beauty"):
            v = _one(race, scene=scene, method=b["method"], layers="vbl", layer="volume_from_volume")
            t_m = score.time_to_rmae(b["rmae_at_budget"], b["budget_s"], RMAE13)
            vr = ptv["rmae_at_budget"] / v["rmae_at_budget"] if v and ptv and v["rmae_at_budget"] > 0 else float("nan")
            out.append(f"| {scene} | {b['method']} | {b['passes']} | {b['cpu_s']:.1f} | {_f(b['rmae_at_budget'])} | "
                       f"{_f(v['rmae_at_budget'] if v else None)} | {_f(vr, '%.2f')} | {_f(t_m / t_pt, '%.2f')} | "
                       f"{_f(b['energy'], '%.3f')} | {_f(v['energy'] if v else None, '%.3f')} | "
                       f"{b['fireflies'] - ptb['fireflies']} |")
    return out


def table_layers(race):
    out = ["## Every layer, every method (rMAE at the budget; the reference's own floor last)", "",
           "| scene | layer | " + " | ".join(race.a.methods) + " | ref floor |",
           "|---|---|" + "---:|" * (len(race.a.methods) + 1)]
    for scene in race.a.scenes:
        layers = []
        for r in _rows(race, scene=scene, layers="vbl"):
            if r["layer"] not in layers:
                layers.append(r["layer"])
        for layer in layers:
            cells = []
            floor = None
            for m in race.a.methods:
                r = _one(race, scene=scene, method=m, layers="vbl", layer=layer)
                cells.append(_f(r["rmae_at_budget"]) if r else "")
                floor = r["ref_floor"] if r else floor
            out.append(f"| {scene} | {layer} | " + " | ".join(cells) + f" | {_f(floor)} |")
    return out


def table_checks(race):
    out = ["## Reference check: mean of the two Cycles renders over the pt reference's, per Cycles pass", "",
           "Agreement: |ratio - 1| <= max(2%, 3 sigma), sigma from the two Cycles seeds and the two reference halves (the larger of their totals' spread and their pixels').", "",
           "| scene | pass | Cycles / pt | sigma | agree |", "|---|---|---:|---:|---|"]
    for c in race.checks:
        out.append(f"| {c['scene']} | {c['layer']} | {c['cycles_over_pt']:.4f} | {c['sigma']:.4f} | "
                   f"{'yes' if c['agree'] else '**no**'} |")
    return out


def header(race, a):
    try:
        commit = subprocess.run(["git", "-C", os.path.dirname(__file__), "log", "-1", "--format=%h %s"],
                                capture_output=True, text=True).stdout.strip()
    except OSError:
        commit = "?"
    loads = ", ".join("/".join(l) for l in race.uptime)
    return [f"# Cycles race (bench/race_cycles/run.sh{' --quick' if a.quick else ''})", "",
            f"- {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}",
            f"- {platform.machine()}, {os.cpu_count()} cores; load average (1/5/15 min) at the start and after each scene: {loads}",
            f"- Cycles 3.4 CPU {a.spp} spp, 2 threads (../shared/tools/cycles-reference/render.sh --passes), two renders "
            f"(seeds 0 and 1): the mean of their whole-process CPU times (user + system, getrusage) is the budget and the "
            f"mean of their rMAE is Cycles' error (the first render alone where --check-spp differs from --spp); "
            f"scenes without a Cycles race: {a.budget:.0f} CPU s",
            f"- libvbl: each method with its defaults, 2 threads, passes sized to the budget from a one-pass calibration run",
            f"- reference: pt, two halves of {a.ref_factor:g}x the budget each; rMAE = sum|img - ref| / sum|ref| over pixels and RGB",
            f"- wall time of the whole run: {race.elapsed:.0f} s", ""]


COLORS = {"cycles": "tab:blue", "pt": "tab:orange", "vrl": "tab:green", "vbl": "tab:red", "vpl": "tab:brown",
          "beams": "tab:purple"}


def plot(race, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = [s for s in race.a.scenes if _rows(race, scene=s, layers="vbl")]
    fig, axes = plt.subplots(1, len(scenes), figsize=(3.2 * len(scenes), 3.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        methods = (["cycles"] if _rows(race, scene=scene, method="cycles") else []) + \
            [m for m in race.a.methods if _rows(race, scene=scene, method=m)]
        layers = ["beauty", "volume_direct", "volume_from_volume", "surface_direct"]
        layers = [l for l in layers if _one(race, scene=scene, method="pt", layers="vbl", layer=l)]
        width = 0.8 / len(methods)
        for i, m in enumerate(methods):
            vals = []
            for l in layers:
                kind, name = ("cycles", {"surface_direct": "diffuse_direct"}.get(l, l)) if m == "cycles" else ("vbl", l)
                if m == "cycles" and l == "volume_from_volume":
                    name = "volume_indirect"
                r = _one(race, scene=scene, method=m, layers=kind, layer=name)
                vals.append(r["rmae_at_budget"] if r else float("nan"))
            ax.bar([j + i * width for j in range(len(layers))], vals, width, label=m, color=COLORS.get(m, "grey"))
        ax.set_xticks([j + 0.4 - width / 2 for j in range(len(layers))])
        ax.set_xticklabels([l.replace("volume_", "vol_").replace("surface_", "surf_") for l in layers], rotation=30, fontsize=7)
        ax.set_yscale("log")
        ax.set_title(scene, fontsize=9)
    axes[0][0].set_ylabel("rMAE at Cycles' CPU time")
    from matplotlib.patches import Patch
    fig.legend(handles=[Patch(color=c, label=m) for m, c in COLORS.items()], loc="upper right", fontsize=7, ncol=6)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    fig.savefig(path, dpi=90)


def cycles_times(race):
    out = ["## Cycles' time (the budget): whole process vs the render call", "",
           "Whole process: Blender start, scene set-up, VDB load, BVH, path tracing, EXR and pass split. Render call: "
           "bpy.ops.render.render alone (wall).", "",
           "| scene | CPU s (budget) | process wall s | render call wall s |", "|---|---:|---:|---:|"]
    for scene, c in getattr(race, "cycles_info", {}).items():
        out.append(f"| {scene} | {c['cpu_s']:.1f} | {c['wall_s']:.1f} | {c['render_call_wall_s']:.1f} |")
    skipped = getattr(race, "skipped", [])
    if skipped:
        out += ["", "Not raced (the calibration pass was stopped): " +
                "; ".join(f"{k['scene']} {k['method']}: {k['note']}" for k in skipped)]
    return out


class _Saved:
    """A race read back from its STEM.json (report.rewrite)."""
    def __init__(self, d):
        self.rows, self.checks, self.uptime, self.elapsed = d["rows"], d["checks"], d["uptime"], d["elapsed"]
        self.cycles_info = d.get("cycles_info", {})
        self.skipped = d.get("skipped", [])
        self.a = argparse.Namespace(**d["args"])


def rewrite(path, plot_path):
    d = json.load(open(path))
    race = _Saved(d)
    race.a.out = path[:-5]
    race.a.plot = plot_path if race.a.plot else None
    write(race, race.a)


def write(race, a, quiet=False):
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    keep = ("quick", "spp", "check_spp", "ref_factor", "budget", "scenes", "methods", "plot")
    json.dump(dict(rows=race.rows, checks=race.checks, uptime=race.uptime, elapsed=race.elapsed,
                   cycles_info=getattr(race, "cycles_info", {}), skipped=getattr(race, "skipped", []), args={k: getattr(a, k) for k in keep}),
              open(a.out + ".json", "w"), indent=0)
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(race.rows[0].keys()))
        w.writeheader()
        w.writerows(race.rows)
    text = header(race, a) + table14(race) + [""] + table13(race) + [""] + table_layers(race) + [""] + table_checks(race) + [""] + cycles_times(race)
    text.append("")
    text.append("(cycles_vol_indirect in the plot and the Cycles table: volume_from_surface + volume_from_volume; "
                "diffuse_indirect: surface_from_surface + surface_from_volume)")
    open(a.out + ".txt", "w").write("\n".join(text) + "\n")
    if not quiet:
        print("\n".join(text))
    if a.plot:
        plot(race, a.plot)
