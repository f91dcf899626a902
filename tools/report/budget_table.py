"""The frame-budget table of a render's timing report (`cpurender render ... --out DIR` -> DIR/report.json).

The report's summary has no per-pass p99, so every row is computed from the per-frame records, with
the engine's percentile method (engine/output/percentile.cpp), so p50 and p95 match the summary's.
"""
import math
from dataclasses import dataclass


class TimingError(ValueError):
    pass


@dataclass
class BudgetRow:
    name: str                  # a pass name, or "frame"
    frames_run: int
    p50: float
    p95: float
    p99: float
    amortized_ms: float        # total time over all frames / frame count

    def over_budget(self, stat, budget_ms):
        return is_over_budget(getattr(self, stat), budget_ms)


@dataclass
class BudgetTable:
    scene: str
    profile: str
    frames: int
    threads: int
    budget_ms: float           # 0: the profile sets no frame budget
    frames_over_budget: int
    frame: BudgetRow
    passes: list               # BudgetRow per pass, in order of first appearance


def is_over_budget(ms, budget_ms):
    """A budget of 0 is no budget."""
    return budget_ms > 0 and ms > budget_ms


def percentile_nearest_rank(samples, p):
    """The smallest sample with at least p% of the samples <= it: 1-based rank ceil(p/100*n)."""
    if not samples:
        return 0.0
    ordered = sorted(samples)
    # Rounded to 1e-9 before ceil as the engine does (0.95 * 100 is 95.00000000000001 in binary, and
    # p95 of 100 samples is rank 95); floor(x + 0.5) is C++'s std::round for x >= 0.
    position = math.floor(min(max(p, 0.0), 100.0) / 100 * len(ordered) * 1e9 + 0.5) / 1e9
    rank = max(1, math.ceil(position))
    return ordered[min(rank, len(ordered)) - 1]


def _row(name, samples, frame_count):
    return BudgetRow(name=name, frames_run=len(samples),
                     p50=percentile_nearest_rank(samples, 50),
                     p95=percentile_nearest_rank(samples, 95),
                     p99=percentile_nearest_rank(samples, 99),
                     amortized_ms=sum(samples) / frame_count)


def budget_table(report):
    """The table of a parsed report.json."""
    frames = report.get('frames')
    if not isinstance(frames, list) or not frames:
        raise TimingError('the report has no per-frame records ("frames")')
    pass_samples = {}  # insertion order = first appearance, as in the engine's summary
    try:
        frame_ms = [float(f['frame_ms']) for f in frames]
        for f in frames:
            for p in f['passes']:
                pass_samples.setdefault(p['name'], []).append(float(p['ms']))
    except (KeyError, TypeError, ValueError) as e:
        raise TimingError(f'a frame record lacks a field: {e}') from e
    summary = report.get('summary') or {}
    budget_ms = float(summary.get('frame_budget_ms') or 0.0)
    return BudgetTable(scene=str(report.get('scene', '')), profile=str(report.get('profile', '')),
                       frames=len(frames), threads=int(report.get('threads', 0)), budget_ms=budget_ms,
                       frames_over_budget=sum(1 for ms in frame_ms if is_over_budget(ms, budget_ms)),
                       frame=_row('frame', frame_ms, len(frames)),
                       passes=[_row(name, s, len(frames)) for name, s in pass_samples.items()])

