#!/usr/bin/python3
"""Error-vs-time plot of bench_curves' CSV files (issues 4 and 6).

    /usr/bin/python3 bench/plot_curves.py bench/results/curves.csv [MORE.csv ...] \\
        -o docs/images/error_vs_time.png [--layer medium|beauty|volume_from_volume|...]
    /usr/bin/python3 bench/plot_curves.py bench/results/curves.csv \\
        -o docs/images/error_vs_time_smoky_room_layers.png --layers-of smoky_room

Log-log rMAE (against the long pt reference) vs seconds, one panel per scene (three per row),
one line per method (solid) or quality preset (dashed, dot at its final pass); grey dotted lines
at 0.1 and 0.05, and the reference's own error (rows "reference_floor") as a thin black line.
--layers-of SCENE instead draws one panel per layer (beauty and every transport layer the
scene has) of that scene. A later CSV replaces an earlier one's curve of the same scene and
method (e.g. a --presets-only re-run). Run it with Debian's python3 (python3-matplotlib); no
other dependencies.
"""
import argparse
import csv
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PRESETS = ("preview", "production", "final")
TITLES = {
    "cloud": "sample cloud (density 12, albedo 0.95, g = 0.5)",
    "dense": "dense cloud (density 48, albedo 0.95, g = 0.8)",
    "smoky_room": "smoky room (plume, Phong floor, GGX box, spot light)",
}
LAYERS = ("beauty", "surface_direct", "volume_direct", "surface_from_surface", "surface_from_volume",
          "volume_from_surface", "volume_from_volume")


def read(paths, layer):
    column = "rmae_" + layer
    data = OrderedDict()  # scene -> method -> ([t], [e])
    floors = {}
    for path in paths:
        seen = set()
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if column not in row:
                    sys.exit("plot_curves: %s has no column %s" % (path, column))
                if not row[column]:
                    continue
                scene, method = row["scene"], row["method"]
                t, e = float(row["seconds"]), float(row[column])
                if method == "reference_floor":
                    floors[scene] = e
                    continue
                if t <= 0 or e <= 0:
                    continue
                runs = data.setdefault(scene, OrderedDict())
                if (scene, method) not in seen:  # this file's curve replaces an earlier file's
                    seen.add((scene, method))
                    runs[method] = ([], [])
                runs[method][0].append(t)
                runs[method][1].append(e)
    return data, floors


def draw(ax, runs, floor, colors, ylabel, title):
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for method, (ts, es) in runs.items():
        if method not in colors:
            colors[method] = cycle[len(colors) % len(cycle)]
        preset = method in PRESETS
        ax.plot(ts, es, "--" if preset else "-", color=colors[method], lw=1.4,
                label=("preset " + method) if preset else method)
        if preset:
            ax.plot(ts[-1:], es[-1:], "o", color=colors[method], ms=5)
    for y in (0.1, 0.05):
        ax.axhline(y, color="0.5", lw=0.8, ls=":")
        ax.text(1.0, y, " %g" % y, transform=ax.get_yaxis_transform(), va="center", fontsize=8, color="0.4")
    if floor is not None:
        ax.axhline(floor, color="k", lw=0.7)
        ax.text(0.99, floor, "reference's own error %.3f" % floor,
                transform=ax.get_yaxis_transform(), va="bottom", ha="right", fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds (96x72, 2 threads)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(fontsize=8, loc="lower left", framealpha=0.9)


def grid(n):
    cols = min(3, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.2 * cols, 4.8 * rows), squeeze=False)
    flat = [ax for row in axes for ax in row]
    for ax in flat[n:]:
        ax.set_visible(False)
    return fig, flat[:n]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+")
    ap.add_argument("-o", "--output", required=True, help="PNG to write")
    ap.add_argument("--layer", default="medium", help="rmae_<layer> column to plot (default medium)")
    ap.add_argument("--layers-of", metavar="SCENE", help="one panel per layer of this scene")
    args = ap.parse_args()
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]  # the same colour per method in every plot
    colors = {m: cycle[i % len(cycle)] for i, m in enumerate(("pt", "vpl", "vrl", "beams") + PRESETS + ("vbl",))}
    if args.layers_of:
        panels = []
        for layer in LAYERS:
            data, floors = read(args.csv, layer)
            if args.layers_of in data:
                panels.append((layer, data[args.layers_of], floors.get(args.layers_of)))
        if not panels:
            sys.exit("plot_curves: no data of scene %s in %s" % (args.layers_of, ", ".join(args.csv)))
        fig, axes = grid(len(panels))
        for ax, (layer, runs, floor) in zip(axes, panels):
            draw(ax, runs, floor, colors, "rMAE vs long pt reference",
                 "%s: %s" % (TITLES.get(args.layers_of, args.layers_of).split(" (")[0], layer))
    else:
        data, floors = read(args.csv, args.layer)
        if not data:
            sys.exit("plot_curves: no data in %s" % ", ".join(args.csv))
        scenes = list(data)
        fig, axes = grid(len(scenes))
        for ax, scene in zip(axes, scenes):
            draw(ax, data[scene], floors.get(scene), colors, "rMAE of %s vs long pt reference" % args.layer,
                 TITLES.get(scene, scene))
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print("plot_curves: wrote %s" % args.output)


if __name__ == "__main__":
    main()
