#!/usr/bin/python3
"""cpurender_report.py: an HTML report per scene from `cpurender sweep` results and a render's
timing report (docs/report.md).

usage: tools/report/cpurender_report.py --sweep DIR [--sweep DIR2 ...] [--timing report.json ...]
                                        [--plan plan.json] --title NAME --out OUTDIR

Writes OUTDIR/<scene>_report.html (self-contained) and OUTDIR/<scene>_<frame|module>.png/.svg.
Sweeps and timing reports are grouped by the scene they name; a scene with either gets a page.
Needs python3-matplotlib (Debian's /usr/bin/python3).
"""
import argparse
import json
import sys
from pathlib import Path

from budget_table import TimingError, budget_table
from html_report import write_html
from scene_report import build_scene_report
from settings_plan import PlanError, find_plan, load_settings, plan_settings
from sweep_data import SweepError, load_sweep, scene_name


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--sweep', action='append', default=[], metavar='DIR',
                        help='a sweep output directory (or its sweep.json); repeat to merge sweeps')
    parser.add_argument('--timing', action='append', default=[], metavar='REPORT',
                        help="a render's report.json, for the frame-budget table; one per scene")
    parser.add_argument('--plan', metavar='FILE',
                        help='the settings chosen: a plan ({"choices": [...]}), a report.json with a '
                             '"plan", or a profile; default: the plan in the timing report, if any')
    parser.add_argument('--title', required=True, help='the report title (a scene name is appended)')
    parser.add_argument('--out', required=True, metavar='OUTDIR')
    args = parser.parse_args(argv)
    if not args.sweep and not args.timing:
        parser.error('give at least one --sweep or --timing')
    return args


def load_timing(path):
    """(scene name, budget table, the plan it carries or None) of a report.json."""
    try:
        report = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise TimingError(f'{path}: {e}') from e
    if not isinstance(report, dict) or not report.get('scene'):
        raise TimingError(f'{path}: not a timing report (no "scene")')
    try:
        table = budget_table(report)
    except TimingError as e:
        raise TimingError(f'{path}: {e}') from e
    plan = find_plan(report)
    return scene_name(report['scene']), table, plan_settings(plan, path) if plan else None


def main(argv):
    args = parse_args(argv)
    try:
        sweeps = {}
        for path in args.sweep:
            sweep = load_sweep(path)
            sweeps.setdefault(sweep.scene_name, []).append(sweep)
        timings = {}
        for path in args.timing:
            scene, table, plan = load_timing(path)
            if scene in timings:
                raise TimingError(f'{path}: a second timing report of scene {scene}')
            timings[scene] = (path, table, plan)
        given_plan = load_settings(args.plan) if args.plan else None
    except (SweepError, TimingError, PlanError) as e:
        print(f'cpurender_report: {e}', file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for scene in sorted(set(sweeps) | set(timings)):
        timing_path, table, timing_plan = timings.get(scene, (None, None, None))
        report = build_scene_report(args.title, scene, sweeps.get(scene, []), table,
                                    given_plan or timing_plan, out, timing_path)
        print(f'wrote {write_html(report, out)}')
        for chart in report.charts:
            if chart.skipped:
                print(f'  {scene} {chart.module}: no chart: {chart.skipped}')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
