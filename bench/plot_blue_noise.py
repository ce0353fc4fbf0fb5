#!/usr/bin/python3
"""Error-vs-time plot of bench_blue_noise's CSV (issue 8).

    /usr/bin/python3 bench/plot_blue_noise.py bench/results/blue_noise.csv \\
        docs/images/blue_noise_error_vs_time.png [--layers surface_from_surface,beauty]

One row per layer (default surface_from_surface, then beauty), one column per scene: log-log
rMAE against seconds, one line per configuration of the equal-time runs (rows with experiment
"time"; bn_ext_N solid, bn_noext_N dotted, one colour per N), and the pt reference's own error
(rows "reference_floor") as a thin black line. Run it with Debian's
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
}
STYLES = {
    "pt": dict(color="black", linestyle="--"),
    "lp": dict(color="tab:blue"),
    "lp_clamp": dict(color="tab:cyan"),
}
BN_COLORS = ["tab:orange", "tab:red", "darkred", "purple"]


def label(config):
    """bn_ext_16384 -> 'vpl, blue-noise VSLs N=16384 + extension'."""
    if config in LABELS:
        return LABELS[config]
    if config.startswith("bn_ext_"):
        return "vpl, blue-noise VSLs, N=%s + extension" % config[len("bn_ext_"):]
    if config.startswith("bn_noext_"):
        return "vpl, blue-noise VSLs, N=%s, no extension" % config[len("bn_noext_"):]
    return config


def style(config, bn_order):
    if config in STYLES:
        return STYLES[config]
    n = config.rsplit("_", 1)[-1]
    color = BN_COLORS[bn_order.index(n) % len(BN_COLORS)] if n in bn_order else "gray"
    return dict(color=color, linestyle=":" if config.startswith("bn_noext") else "-", marker=".")


def read(path, layers):
    """layer -> scene -> config -> ([seconds], [rMAE]); layer -> scene -> reference floor."""
    curves = {layer: OrderedDict() for layer in layers}
    floors = {layer: {} for layer in layers}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            for layer in layers:
                value = row.get("rmae_" + layer, "")
                if not value or value == "nan":
                    continue
                scene, value = row["scene"], float(value)
                if row["experiment"] == "reference_floor":
                    floors[layer][scene] = value
                    continue
                if row["experiment"] != "time":
                    continue
                t = float(row["seconds"])
                if t <= 0 or value <= 0:
                    continue
                ts, es = curves[layer].setdefault(scene, OrderedDict()).setdefault(row["config"], ([], []))
                ts.append(t)
                es.append(value)
    return curves, floors


def plot(curves, floors, layers, out):
    scenes = list(OrderedDict.fromkeys(s for layer in layers for s in curves[layer]))
    cols = max(1, len(scenes))
    fig, axes = plt.subplots(len(layers), cols, figsize=(6.2 * cols, 4.6 * len(layers)), squeeze=False)
    for r, layer in enumerate(layers):
        for ax, scene in zip(axes[r], scenes):
            configs = curves[layer].get(scene, {})
            bn_order = sorted({c.rsplit("_", 1)[-1] for c in configs if c.startswith("bn_")}, key=int)
            for config, (ts, es) in configs.items():
                ax.loglog(ts, es, label=label(config), linewidth=1.6, **style(config, bn_order))
            if scene in floors[layer]:
                ax.axhline(floors[layer][scene], color="black", linewidth=0.6, label="pt reference's own rMAE")
            ax.set_title(TITLES.get(scene, scene))
            ax.set_xlabel("seconds (2 threads, loaded 2-core machine)")
            ax.set_ylabel("rMAE of " + layer)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("out")
    p.add_argument("--layers", default="surface_from_surface,beauty",
                   help="comma-separated rows: surface_from_surface, volume_from_surface, beauty")
    a = p.parse_args()
    layers = a.layers.split(",")
    curves, floors = read(a.csv, layers)
    plot(curves, floors, layers, a.out)

if __name__ == "__main__":
    main()
