#!/usr/bin/python3
"""Draws the heat maps of a stability.json (sky-stability, fog-stability; schema in docs/stability.md).

Per grid, one PNG and one SVG (<out>/<prefix><grid>.png|svg): the mean relative error against the ground truth
(log colour scale) with the thresholds' contours, beside the ground truth's own noise on the same scale; a marker
at its own corner of a cell shows each fallback that engaged there (any share > 0), and a red X marks any cell
with a non-finite value. Grey cells have nothing to score (the reference is below its dark floor everywhere).
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

# Per fallback, a marker at its own corner of the cell (marker, x offset, y offset).
MARKERS = [("^", -0.28, 0.28), ("s", 0.28, 0.28), ("D", -0.28, -0.28), ("v", 0.28, -0.28), ("o", 0.0, 0.3),
           ("P", 0.0, -0.3)]
FLOOR = 1e-3  # errors below this are drawn at it (log scale)
CEILING = 1.0  # and above this (100%) at it, so that the range around the thresholds keeps its colours


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
    # Only the thresholds the data crosses (matplotlib warns on the others).
    colors = dict(zip(thresholds, ["white", "red", "orange"]))
    levels = [t for t in thresholds if np.nanmin(data, initial=np.inf) < t < np.nanmax(data, initial=-np.inf)]
    if field == "error_mean" and nx > 1 and ny > 1 and levels:
        cs = ax.contour(np.arange(nx), np.arange(ny), np.ma.masked_invalid(data), levels=levels,
                        colors=[colors[t] for t in levels], linewidths=1.5)
        ax.clabel(cs, fmt={t: f"{100 * t:g}%" for t in levels}, fontsize=7)
    handles = []
    for k, name in enumerate(grid["fallbacks"]):
        marker, dx, dy = MARKERS[k % len(MARKERS)]
        cells = [c for c in grid["cells"] if c["fallbacks"].get(name, 0) > 0]
        if cells:
            ax.scatter([c["x"] + dx for c in cells], [c["y"] + dy for c in cells], marker=marker, s=22,
                       facecolors="white", edgecolors="black", linewidths=0.8, zorder=4)
            handles.append(plt.Line2D([], [], marker=marker, markerfacecolor="white", markeredgecolor="black",
                                      color="none", label=f"{name} engaged"))
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
    top = min(max(float(finite.max()) if finite.size else 1.0, max(thresholds) * 2), CEILING)
    norm = LogNorm(vmin=FLOOR, vmax=top, clip=True)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
    im, handles = draw_panel(axes[0], grid, "error_mean", "mean relative error vs ground truth", norm, thresholds)
    draw_panel(axes[1], grid, "noise_mean", "ground truth's own noise (mean)", norm, thresholds)
    fig.colorbar(im, ax=axes, label="relative luminance error (log; clipped at 0.1% and 100%)")
    if handles:
        axes[0].legend(handles=handles, loc="upper left", bbox_to_anchor=(0.0, -0.28), ncol=3, fontsize=7,
                       frameon=False)
    fixed = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in grid.get("fixed", {}).items())
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
