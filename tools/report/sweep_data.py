"""Loading a `cpurender sweep` result (sweep.json) and reading per-point module time and error from it.

Required fields are checked on load, so a malformed file fails with its path and the missing field
rather than deep inside a chart. Optional fields (per pass "mean", per point "label" and
"module_error") are used when present.
"""
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

# The chart key of the whole frame; every other key is a module (the prefix of its passes' names).
FRAME = 'frame'


class SweepError(ValueError):
    pass


@dataclass
class Point:
    id: str
    source: str                      # the sweep directory's name, to tell merged sweeps apart
    settings: dict
    threads: int
    frame_ms_p50: float
    frame_ms_p95: float
    passes: dict                     # pass name -> {"p50", "p95", optional "mean", "p99"}
    error: dict | None               # {"rel_luminance_mean", ...}; None when the point has no reference
    label: str | None = None         # a named profile to mark on charts ("desktop", "mobile", "auto")
    module_error: dict = field(default_factory=dict)


@dataclass
class Sweep:
    path: Path
    scene: str                       # the scene file as the sweep names it
    points: list

    @property
    def scene_name(self):
        return scene_name(self.scene)


@dataclass
class Measurement:
    point: Point
    time_ms: float
    error: float


def scene_name(scene_path):
    return Path(scene_path).stem


def module_of(pass_name):
    """The module a pass belongs to ("fog" for "fog.lighting"), None for an engine pass."""
    return pass_name.split('.', 1)[0] if '.' in pass_name else None


def _number(value, where):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SweepError(f'{where}: expected a finite number, got {value!r}')
    return float(value)


def _require(obj, key, where):
    if not isinstance(obj, dict) or key not in obj:
        raise SweepError(f'{where}: missing "{key}"')
    return obj[key]


def _load_point(row, source, where):
    passes = _require(row, 'passes', where)
    if not isinstance(passes, dict):
        raise SweepError(f'{where}: "passes" is not an object')
    for name, stats in passes.items():
        for stat in ('p50', 'p95'):
            _number(_require(stats, stat, f'{where} pass "{name}"'), f'{where} pass "{name}" {stat}')
        for stat in ('mean', 'p99'):
            if stats.get(stat) is not None:
                _number(stats[stat], f'{where} pass "{name}" {stat}')
    error = row.get('error')
    if error is not None and not isinstance(error, dict):
        raise SweepError(f'{where}: "error" is not an object')
    module_error = row.get('module_error') or {}
    if not isinstance(module_error, dict):
        raise SweepError(f'{where}: "module_error" is not an object')
    return Point(id=str(_require(row, 'point', where)),
                 source=source,
                 settings=_require(row, 'settings', where),
                 threads=int(_require(row, 'threads', where)),
                 frame_ms_p50=_number(_require(row, 'frame_ms_p50', where), f'{where} frame_ms_p50'),
                 frame_ms_p95=_number(_require(row, 'frame_ms_p95', where), f'{where} frame_ms_p95'),
                 passes=passes,
                 error=error,
                 label=row.get('label'),
                 module_error=module_error)


def load_sweep(path):
    """Reads a sweep.json, or the sweep.json in a directory."""
    path = Path(path)
    if path.is_dir():
        path = path / 'sweep.json'
    try:
        doc = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise SweepError(f'{path}: {e}') from e
    scene = _require(doc, 'scene', str(path))
    rows = _require(doc, 'points', str(path))
    if not isinstance(rows, list):
        raise SweepError(f'{path}: "points" is not a list')
    source = path.parent.name
    points = [_load_point(row, source, f'{path} point {i}') for i, row in enumerate(rows)]
    return Sweep(path=path, scene=scene, points=points)


def modules(points):
    """The modules with passes in any of the points, sorted."""
    return sorted({m for p in points for name in p.passes if (m := module_of(name)) is not None})


def pass_time_ms(stats):
    # The amortised mean counts a LUT pass that runs every few frames at its share of every frame;
    # its p50 is the time of a frame that ran it (or 0), which misstates the cost either way.
    return float(stats['mean']) if stats.get('mean') is not None else float(stats['p50'])


def time_basis(points, module):
    """How time_ms measured the module in these points, for an axis label."""
    if module == FRAME:
        return 'frame p50'
    has_mean = {s.get('mean') is not None for p in points for name, s in p.passes.items()
                if module_of(name) == module}
    if has_mean == {True}:
        return 'sum of passes\' amortised means'
    if has_mean == {False}:
        return 'sum of passes\' p50'
    return 'sum of passes\' amortised means, p50 where absent'


def time_ms(point, module):
    """The point's ms per frame: the frame's p50 for FRAME, else the sum over the module's passes
    (None when the point ran none of them)."""
    if module == FRAME:
        return point.frame_ms_p50
    times = [pass_time_ms(s) for name, s in point.passes.items() if module_of(name) == module]
    return sum(times) if times else None


def error(point, module):
    """The point's mean relative luminance error: of the frame for FRAME, else of the module against
    its own ground truth. None when the sweep did not record it."""
    source = point.error if module == FRAME else point.module_error.get(module)
    value = (source or {}).get('rel_luminance_mean')
    return None if value is None else float(value)


def measurements(points, module):
    """The points that have both a time and a plottable (positive) error for the module, and a note
    for each point left out. A log axis cannot show a zero error, and a missing one is not guessed."""
    kept, notes = [], []
    for p in points:
        t, e = time_ms(p, module), error(p, module)
        if t is None:
            notes.append(f'{p.id}: no {module} passes')
        elif e is None:
            notes.append(f'{p.id}: no error recorded')
        elif e <= 0:
            notes.append(f'{p.id}: error {e:g} cannot be drawn on a log axis')
        else:
            kept.append(Measurement(point=p, time_ms=t, error=e))
    return kept, notes
