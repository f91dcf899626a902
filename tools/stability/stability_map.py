#!/usr/bin/python3
"""Draws the heat maps of a stability.json (sky-stability, fog-stability; schema in docs/stability.md).

Per grid, one PNG and one SVG (<out>/<prefix><grid>.png|svg): the mean relative error against the ground truth
(log colour scale) with the thresholds' contours, beside the ground truth's own noise on the same scale; each
fallback that engaged is hatched over its cells, and a red X marks any cell with a non-finite value.
Cells are drawn by index (equal size), labelled with the axis values.

Usage: /usr/bin/python3 tools/stability/stability_map.py STABILITY_JSON [--out DIR] [--prefix NAME]
(Debian's python3-matplotlib.)
"""
import argparse
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402

HATCHES = ["///", "\\\\\\", "...", "xx", "++", "oo"]
FLOOR = 1e-4  # errors below this are drawn at it (log scale)


def values(grid, key):
    """The cells' `key` as an array [y, x]; NaN where a cell is not scored or the value is missing."""
    a = np.full((len(grid["y"]["values"]), len(grid["x"]["values"])), np.nan)
    for c in grid["cells"]:
        v = c[key]
        if c["scored"] and v is not None:
            a[c["y"], c["x"]] = max(v, FLOOR)
    return a


def label(v):
    return f"{v:g}"


def draw_panel(ax, grid, field, title, norm, thresholds):
    data = values(grid, field)
    cmap = matplotlib.colormaps["viridis"].copy()
    cmap.set_bad("0.8")  # unscored cells: grey
    im = ax.imshow(data, origin="lower", cmap=cmap, norm=norm, aspect="auto", interpolation="nearest")
    ny, nx = data.shape
    if field == "error_mean" and nx > 1 and ny > 1:
        filled = np.where(np.isnan(data), FLOOR, data)
        cs = ax.contour(np.arange(nx), np.arange(ny), filled, levels=thresholds, colors=["white", "red"][: len(thresholds)],
                        linewidths=1.5)
        ax.clabel(cs, fmt={t: f"{100 * t:g}%" for t in thresholds}, fontsize=7)
    handles = []
    for k, name in enumerate(grid["fallbacks"]):
        hatch = HATCHES[k % len(HATCHES)]
        engaged = False
        for c in grid["cells"]:
            if c["fallbacks"].get(name, 0) > 0:
                engaged = True
                ax.add_patch(Rectangle((c["x"] - 0.5, c["y"] - 0.5), 1, 1, fill=False, hatch=hatch, edgecolor="black",
                                       linewidth=0))
        if engaged:
            handles.append(Patch(facecolor="none", edgecolor="black", hatch=hatch, label=name))
    bad = [(c["x"], c["y"]) for c in grid["cells"] if c["non_finite"] > 0]
    if bad:
        xs, ys = zip(*bad)
        ax.scatter(xs, ys, marker="x", s=80, c="red", linewidths=2.5, zorder=5)
        handles.append(plt.Line2D([], [], marker="x", color="red", linestyle="none", label="non-finite"))
    ax.set_xticks(range(nx))
    ax.set_xticklabels([label(v) for v in grid["x"]["values"]], rotation=60, fontsize=7)
    ax.set_yticks(range(ny))
    ax.set_yticklabels([label(v) for v in grid["y"]["values"]], fontsize=7)
    ax.set_xlabel(grid["x"]["name"])
    ax.set_ylabel(grid["y"]["name"])
    ax.set_title(title, fontsize=9)
    return im, handles


def draw_grid(doc, grid, path_stem):
    thresholds = sorted(doc["thresholds"])
    errors = values(grid, "error_mean")
    noise = values(grid, "noise_mean")
    finite = np.concatenate([errors[~np.isnan(errors)], noise[~np.isnan(noise)]])
    top = max(float(finite.max()) if finite.size else 1.0, max(thresholds) * 2)
    norm = LogNorm(vmin=FLOOR, vmax=top)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
    im, handles = draw_panel(axes[0], grid, "error_mean", "mean relative error vs ground truth", norm, thresholds)
    draw_panel(axes[1], grid, "noise_mean", "ground truth's own noise (mean)", norm, thresholds)
    fig.colorbar(im, ax=axes, label="relative luminance error (log)")
    if handles:
        axes[0].legend(handles=handles, loc="upper left", bbox_to_anchor=(0.0, -0.28), ncol=3, fontsize=7,
                       frameon=False)
    fixed = ", ".join(f"{k} {v}" for k, v in grid.get("fixed", {}).items())
    fig.suptitle(f"{doc['method']}: {grid['name']}" + (f" ({fixed})" if fixed else "") +
                 f"; contours at {', '.join(f'{100 * t:g}%' for t in thresholds)}", fontsize=10)
    for ext in ("png", "svg"):
        fig.savefig(f"{path_stem}.{ext}", dpi=80)
    plt.close(fig)
    return [f"{path_stem}.png", f"{path_stem}.svg"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("json")
    ap.add_argument("--out", help="output directory (default: the JSON's)")
    ap.add_argument("--prefix", default="", help="prefix of the file names (e.g. sky_)")
    a = ap.parse_args()
    with open(a.json) as f:
        doc = json.load(f)
    if doc.get("schema") != "cpurender-stability/1":
        raise SystemExit(f"{a.json}: not a cpurender-stability/1 file")
    out = a.out or os.path.dirname(os.path.abspath(a.json))
    os.makedirs(out, exist_ok=True)
    for grid in doc["grids"]:
        for p in draw_grid(doc, grid, os.path.join(out, a.prefix + grid["name"])):
            print(p)


if __name__ == "__main__":
    main()
