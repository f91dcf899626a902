#!/usr/bin/env python3
"""auto_table.py: measures the options the `auto` planner chooses among and writes its table
(profiles/planner/auto_table.json; docs/planner.md).

For every module of a frame (the engine's passes, the atmosphere, the fog) the options below are
rendered on the scenes that use the module. Two sweeps per scene:
  error  each option as the table's reference profile with only that module's keys changed, so the
         whole frame's error against the reference render is that option's own; on a scene whose
         camera or sun moves, at the start of its path and again at its end (--first-frame), since
         a path's error changes along it (a setting sun's grows);
  cost   each option as the desktop profile with that module's keys changed, so a module's passes
         run beside the other modules' shipped settings rather than the reference's (whose LUTs
         rebuild every frame at 15 wavelengths).

  cpurender sweep SCENE --points FILE --reference REF --resolution 1280x720 --threads 2 ...

Per option the table keeps
  error          the largest mean relative luminance error of the last frame over the scenes,
  errors         the error on each scene (the larger of its windows) with the scene's kind (camera
                 or sun moving; sun within 6 degrees of the horizon): the planner takes the largest
                 over scenes of the planned scene's kind,
  cost_ms        the largest per-frame cost of the module's passes (amortised over the measured
                 frames) over the scenes where the camera or the sun moves,
  static_cost_ms the same over the scenes where both hold still (LUTs are then built once).
The reference is table_reference.py's.

A benchmark, not a test: minutes on two cores. Run it on an otherwise idle machine:
  tools/planner/auto_table.py [--build build] [--out out/auto_table] [--write profiles/planner/auto_table.json]
"""
import argparse, json, os, platform, subprocess, sys

from table_reference import DESCRIPTION, reference_profile

THREADS = 2

# Each option: a name and the profile keys it sets (dotted paths into the profile).
OPTIONS = {
    "engine": [
        ("msaa4", {"antialiasing": "msaa4", "shadow_map_size": 2048, "render_scale": 1}),
        ("msaa2", {"antialiasing": "msaa2", "shadow_map_size": 2048, "render_scale": 1}),
        ("no AA", {"antialiasing": "none", "shadow_map_size": 2048, "render_scale": 1}),
        ("no AA, 1024 shadow map", {"antialiasing": "none", "shadow_map_size": 1024, "render_scale": 1}),
        ("scale 0.85, no AA", {"antialiasing": "none", "shadow_map_size": 2048, "render_scale": 0.85}),
        ("scale 0.75, no AA", {"antialiasing": "none", "shadow_map_size": 2048, "render_scale": 0.75}),
        ("scale 0.75, no AA, 1024 shadow map", {"antialiasing": "none", "shadow_map_size": 1024, "render_scale": 0.75}),
        ("scale 0.6, no AA", {"antialiasing": "none", "shadow_map_size": 2048, "render_scale": 0.6}),
    ],
    "atmosphere": [
        ("6 wavelengths", {"atmosphere.spectral_samples": 6, "atmosphere.schedule.full": False}),
        ("6 wavelengths, sliced", {"atmosphere.spectral_samples": 6, "atmosphere.schedule.full": False,
                                   "atmosphere.schedule.skyview.slices": 2,
                                   "atmosphere.schedule.aerial_perspective.slices": 3}),
        ("6 wavelengths, sliced, periods x2", {"atmosphere.spectral_samples": 6, "atmosphere.schedule.full": False,
                                               "atmosphere.schedule.skyview.period": 8,
                                               "atmosphere.schedule.skyview.slices": 2,
                                               "atmosphere.schedule.aerial_perspective.period": 12,
                                               "atmosphere.schedule.aerial_perspective.slices": 3}),
        ("RGB, sliced", {"atmosphere.spectral_samples": 3, "atmosphere.schedule.full": False,
                         "atmosphere.schedule.skyview.slices": 2,
                         "atmosphere.schedule.aerial_perspective.slices": 3}),
        ("RGB, small LUTs, sliced", {"atmosphere.spectral_samples": 3, "atmosphere.schedule.full": False,
                                     "atmosphere.skyview_lut.width": 96, "atmosphere.skyview_lut.height": 54,
                                     "atmosphere.schedule.skyview.slices": 2,
                                     "atmosphere.schedule.aerial_perspective.slices": 3}),
    ],
    "fog": [
        ("8 px, 64 slices", {"fog.froxel_size_px": 8, "fog.slices": 64}),
        ("8 px, 32 slices", {"fog.froxel_size_px": 8, "fog.slices": 32}),
        ("16 px, 64 slices", {"fog.froxel_size_px": 16, "fog.slices": 64}),
        ("16 px, 32 slices", {"fog.froxel_size_px": 16, "fog.slices": 32}),
    ],
}
# Modules whose work grows with the pixel count (the planner scales their cost to the output).
SCALES_WITH_PIXELS = {"engine": True, "atmosphere": False, "fog": True}

# Scenes, the modules each uses, and their kind as the planner sees it (SceneFacts): whether the camera
# or the sun moves over the frames, and whether the sun comes within 6 degrees of the horizon.
SCENES = [
    ("scenes/fog_valley_flythrough.json", ["engine", "atmosphere", "fog"], True, False),
    ("scenes/sky_sunset_timelapse.json", ["engine", "atmosphere"], True, True),
    ("scenes/default_flythrough.json", ["engine", "atmosphere"], True, False),
    ("scenes/fog_volumes.json", ["engine", "fog"], False, False),
    ("scenes/fog_valley_sunrise.json", ["engine", "atmosphere", "fog"], False, False),
    ("scenes/sky_earth_noon.json", ["engine", "atmosphere"], False, False),
]


def module_cost(row, module):
    """Per-frame ms of a module's passes (engine: the passes without a plugin prefix)."""
    total = 0.0
    for name, p in row["passes"].items():
        owner = name.split(".", 1)[0] if "." in name else "engine"
        if owner == module:
            total += p.get("mean", p["p50"])
    return total


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", default="out/auto_table")
    ap.add_argument("--write", default="profiles/planner/auto_table.json")
    ap.add_argument("--resolution", default="1280x720", help="the table's resolution (the planner scales from it)")
    ap.add_argument("--warmup", type=int, default=4)
    ap.add_argument("--frames", type=int, default=12, help="measured frames per point")
    args = ap.parse_args()
    RESOLUTION = tuple(int(v) for v in args.resolution.split("x"))
    WARMUP, FRAMES = args.warmup, args.frames
    cpurender = os.path.join(args.build, "cpurender")
    os.makedirs(args.out, exist_ok=True)
    desktop_path = "profiles/desktop.json"
    desktop = json.load(open(desktop_path))
    ref_path = os.path.join(args.out, "reference.json")
    json.dump(reference_profile(desktop), open(ref_path, "w"), indent=2)

    measured = {m: {name: {"errors": [], "cost": [], "static": []} for name, _ in opts}
                for m, opts in OPTIONS.items()}

    def sweep(scene, tag, base, modules, first_frame=0):
        """Rows of a sweep of every option of `modules` on `base`, keyed by (module, option)."""
        points = [{"label": f"{m}: {name}", "profile": base, "settings": settings}
                  for m in modules for name, settings in OPTIONS[m]]
        points_file = os.path.join(args.out, f"{tag}.points.json")
        json.dump({"points": points}, open(points_file, "w"), indent=2)
        out = os.path.join(args.out, tag)
        cmd = [cpurender, "sweep", scene, "--points", points_file, "--base", base, "--reference", ref_path,
               "--resolution", f"{RESOLUTION[0]}x{RESOLUTION[1]}", "--threads", str(THREADS),
               "--warmup", str(WARMUP), "--frames", str(FRAMES), "--first-frame", str(first_frame),
               "--out", out, "--resume", "--truth", "none"]
        print(" ".join(cmd), file=sys.stderr)
        subprocess.run(cmd, check=True)
        sweep_path = os.path.join(out, "sweep.json")
        doc = json.load(open(sweep_path))
        # Only this module differs from the reference: the frame's error is the module's
        # (tools/report charts it per module).
        if base == ref_path:
            for row in doc["points"]:
                m = row["label"].split(": ", 1)[0]
                if m != "engine":
                    row["module_error"] = {m: {k: row["error"][k] for k in ("rel_luminance_mean", "rel_luminance_p95")}}
            with open(sweep_path + ".tmp", "w") as f:
                json.dump(doc, f, indent=2)
            os.replace(sweep_path + ".tmp", sweep_path)
        return {tuple(row["label"].split(": ", 1)): row for row in doc["points"]}

    for scene, modules, moving, twilight in SCENES:
        tag = os.path.splitext(os.path.basename(scene))[0]
        path_frames = json.load(open(scene)).get("frames", 1)
        windows = [0]
        if moving and path_frames > 2 * (WARMUP + FRAMES):
            windows.append(path_frames - WARMUP - FRAMES)  # the end of the path
        errors = [sweep(scene, f"{tag}_from_{w}" if w else tag, ref_path, modules, w) for w in windows]
        costs = sweep(scene, f"{tag}_cost", desktop_path, modules)
        for (m, name), row in costs.items():
            entry = measured[m][name]
            error = max(rows[(m, name)]["error"]["rel_luminance_mean"] for rows in errors)
            entry["errors"].append({"scene": scene, "moving": moving, "twilight": twilight, "error": round(error, 5)})
            entry["cost" if moving else "static"].append(module_cost(row, m))

    table = {
        "format": "cpurender-auto-table",
        "measured": {
            "command": "tools/planner/auto_table.py",
            "resolution": list(RESOLUTION), "threads": THREADS, "warmup": WARMUP, "frames": FRAMES,
            "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
            "scenes": [s for s, _, _, _ in SCENES],
            "reference": DESCRIPTION,
            "error": "largest mean relative luminance error of the last frame over the scenes using the module",
            "errors": "the error per scene, with its kind (moving, twilight)",
            "windows": "moving scenes: the error is the larger of the path's first and last frames measured",
            "cost_ms": "largest amortised per-frame cost of the module's passes over the moving scenes, "
                       "the other modules at the desktop profile's settings",
            "static_cost_ms": "the same over the still scenes",
        },
        "modules": {},
    }
    for m, opts in OPTIONS.items():
        rows = []
        for name, settings in opts:
            e = measured[m][name]
            row = {"name": name, "settings": settings, "cost_ms": round(max(e["cost"] or e["static"]), 3),
                   "error": max(x["error"] for x in e["errors"])}
            if e["static"] and m == "atmosphere":
                row["static_cost_ms"] = round(max(e["static"]), 3)
            row["errors"] = e["errors"]
            rows.append(row)
        table["modules"][m] = {"scales_with_pixels": SCALES_WITH_PIXELS[m], "options": rows}
    with open(args.write, "w") as f:
        json.dump(table, f, indent=2)
        f.write("\n")
    print(f"wrote {args.write}")
    for m in table["modules"]:
        for r in table["modules"][m]["options"]:
            print(f"{m:11s} {r['name']:28s} {r['cost_ms']:8.2f} ms  error {100 * r['error']:.2f}%"
                  + (f"  still {r['static_cost_ms']:.2f} ms" if "static_cost_ms" in r else ""))


if __name__ == "__main__":
    main()
