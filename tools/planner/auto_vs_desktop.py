#!/usr/bin/env python3
"""auto_vs_desktop.py: what `--profile auto` buys, per scene, against the shipped profiles
(docs/planner.md, the README's figures).

For each scene:
  cpurender sweep SCENE --point desktop=desktop --point mobile=mobile --point auto=auto
                  --reference REF --resolution 1280x720 --threads 2 ...
      the three profiles' frame time (median and p95 over the measured frames) and error against
      the planner's reference (table_reference.py), all at the same resolution;
  cpurender render SCENE --profile auto --threads 2 [--frames 24]
      the timing report of auto along the scene's whole path, at least 24 frames (a still scene's
      first frame builds its LUTs: one frame of 24 is not its p95), p50/p95/p99 per pass;
  tools/report/cpurender_report.py
      the scene's HTML report (charts, the plan, the frame-budget table).
Prints two Markdown tables: auto against desktop and mobile, and auto's frame budget per scene.

A benchmark, not a test: minutes on two cores; run it on an otherwise idle machine.
usage: tools/planner/auto_vs_desktop.py [--build build] [--out out/auto] [--frames 24]
                                        [--error-budget 0.02] [SCENE ...]
"""
import argparse, json, os, subprocess, sys

from table_reference import reference_profile

HERE = os.path.dirname(os.path.abspath(__file__))
SHIPPED = ["default", "default_flythrough", "engine_only", "fog_valley_flythrough", "fog_valley_sunrise",
           "fog_volumes", "sky_earth_noon", "sky_hazy_morning", "sky_mars", "sky_orbit", "sky_sunset_timelapse"]


def run(cmd):
    print(" ".join(cmd), file=sys.stderr)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", help="scene names in scenes/ (default: every shipped scene)")
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", default="out/auto")
    ap.add_argument("--frames", type=int, default=24, help="measured frames per sweep point")
    ap.add_argument("--warmup", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--error-budget", default="0.02")
    ap.add_argument("--render-frames", type=int, default=24, help="the budget run's least frame count")
    args = ap.parse_args()
    cpurender = os.path.join(args.build, "cpurender")
    os.makedirs(args.out, exist_ok=True)
    ref = os.path.join(args.out, "reference.json")
    json.dump(reference_profile(json.load(open("profiles/desktop.json"))), open(ref, "w"), indent=2)

    compare, budget = [], []
    for name in args.scenes or SHIPPED:
        scene = f"scenes/{name}.json"
        sweep = os.path.join(args.out, name, "sweep")
        run([cpurender, "sweep", scene, "--point", "desktop=desktop", "--point", "mobile=mobile",
             "--point", "auto=auto", "--error-budget", args.error_budget, "--reference", ref,
             "--resolution", "1280x720", "--threads", str(args.threads), "--warmup", str(args.warmup),
             "--frames", str(args.frames), "--out", sweep, "--resume"])
        rows = {r["label"]: r for r in json.load(open(os.path.join(sweep, "sweep.json")))["points"]}
        render = os.path.join(args.out, name, "render")
        frames = max(args.render_frames, json.load(open(scene)).get("frames", 1))
        run([cpurender, "render", scene, "--profile", "auto", "--error-budget", args.error_budget,
             "--frames", str(frames), "--threads", str(args.threads), "--format", "none", "--no-trace", "--quiet", "--out", render])
        report = json.load(open(os.path.join(render, "report.json")))
        run(["/usr/bin/python3", os.path.join(HERE, "..", "report", "cpurender_report.py"), "--sweep", sweep,
             "--timing", os.path.join(render, "report.json"), "--title", "cpurender", "--out",
             os.path.join(args.out, "reports")])

        def cell(label):
            r = rows[label]
            return f"{r['frame_ms_p50']:.1f} / {r['frame_ms_p95']:.1f} ms, {100 * r['error']['rel_luminance_mean']:.2f}%"
        a, d = rows["auto"], rows["desktop"]
        compare.append(f"| {name} | {cell('desktop')} | {cell('mobile')} | {cell('auto')} | "
                       f"{a['frame_ms_p50'] / d['frame_ms_p50']:.2f} |")
        # The budget after warm-up, as the sweep measured it; the render's report (cold start
        # included) goes to the HTML page.
        fog = sum(p.get("mean", 0.0) for n, p in a["passes"].items() if n.startswith("fog."))
        fog_p95 = sum(p["p95"] for n, p in a["passes"].items() if n.startswith("fog."))
        plan = a["plan"]
        s = report["summary"]
        budget.append(f"| {name} | {a['frame_ms_p50']:.1f} | {a['frame_ms_p95']:.1f} | {a['frame_ms_p99']:.1f} | "
                      f"{fog:.2f} / {fog_p95:.2f} | {100 * plan['predicted_error']:.2f}% | "
                      f"{'yes' if a['frame_ms_p95'] <= s['frame_budget_ms'] else 'no'} | "
                      f"{s['frames']}: {s['frame_ms']['p50']:.1f} / {s['frame_ms']['p95']:.1f} |")

    print("\n| scene | desktop p50 / p95, error | mobile p50 / p95, error | auto p50 / p95, error | auto / desktop p50 |")
    print("|---|---|---|---|---|")
    print("\n".join(compare))
    print(f"\n| scene (auto, {args.threads} threads, 1280x720, {args.frames} frames after {args.warmup}) | p50 ms | "
          "p95 ms | p99 ms | fog passes mean / sum of p95 ms | planned error | p95 within budget | "
          "whole path from a cold start: frames, p50 / p95 ms |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(budget))


if __name__ == "__main__":
    main()
