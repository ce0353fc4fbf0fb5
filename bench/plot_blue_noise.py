#!/usr/bin/python3
"""Error-vs-time plot of bench_blue_noise's CSV (issue 8).

    /usr/bin/python3 bench/plot_blue_noise.py bench/results/blue_noise.csv \\
        docs/images/blue_noise_error_vs_time.png [--layer surface_from_surface|beauty]

One panel per scene: log-log rMAE of the layer (default surface_from_surface) against seconds,
one line per configuration of the equal-time runs (rows with experiment "time"), and the pt
reference's own error (rows "reference_floor") as a thin black line. Run it with Debian's
python3 (python3-matplotlib); no other dependencies.
"""
import argparse
import csv
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TITLES = {
    "smoky_room": "smoky room (media + surfaces)",
    "glossy_room": "glossy room (surfaces only)",
}
LABELS = {
    "pt": "pt (baseline)",
    "lp": "vpl, light-path VSLs",
    "lp_clamp": "vpl, light-path VSLs, clamped",
    "bn_ext": "vpl, blue-noise VSLs + path extension",
    "bn_noext": "vpl, blue-noise VSLs, no extension",
}
STYLES = {
    "pt": dict(color="black", linestyle="--"),
    "lp": dict(color="tab:blue"),
    "lp_clamp": dict(color="tab:cyan"),
    "bn_ext": dict(color="tab:red"),
    "bn_noext": dict(color="tab:orange"),
}


def read(path, layer):
    """scene -> config -> ([seconds], [rMAE]); scene -> reference floor."""
    column = "rmae_" + layer
    curves = OrderedDict()
    floors = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if not row[column]:
                continue
            scene, value = row["scene"], float(row[column])
            if row["experiment"] == "reference_floor":
                floors[scene] = value
                continue
            if row["experiment"] != "time":
                continue
            t = float(row["seconds"])
            if t <= 0 or value <= 0:
                continue
            ts, es = curves.setdefault(scene, OrderedDict()).setdefault(row["config"], ([], []))
            ts.append(t)
            es.append(value)
    return curves, floors


def plot(curves, floors, layer, out):
    scenes = list(curves)
    fig, axes = plt.subplots(1, max(1, len(scenes)), figsize=(6.2 * max(1, len(scenes)), 4.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for config, (ts, es) in curves[scene].items():
            ax.loglog(ts, es, label=LABELS.get(config, config), linewidth=1.6, **STYLES.get(config, {}))
        if scene in floors:
            ax.axhline(floors[scene], color="black", linewidth=0.6, label="pt reference's own rMAE")
        ax.set_title(TITLES.get(scene, scene))
        ax.set_xlabel("seconds (2 threads, loaded 2-core machine)")
        ax.set_ylabel("rMAE of " + layer)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("out")
    p.add_argument("--layer", default="surface_from_surface", choices=("surface_from_surface", "beauty"))
    a = p.parse_args()
    curves, floors = read(a.csv, a.layer)
    plot(curves, floors, a.layer, a.out)


if __name__ == "__main__":
    main()
