"""What one scene's report shows: its charts with their Pareto fronts, the settings chosen and the
frame-budget table, gathered from the sweeps and timing report of that scene."""
from dataclasses import dataclass, field
from pathlib import Path

import sweep_data
from charts import error_time_chart
from pareto import pareto_front


@dataclass
class Chart:
    module: str                      # sweep_data.FRAME or a module name
    title: str
    png: str | None = None           # None: skipped, and `skipped` says why
    svg: str | None = None
    front: list = field(default_factory=list)   # Measurements on the front, by increasing time
    plotted: int = 0
    notes: list = field(default_factory=list)   # points left out of the chart, and why
    skipped: str | None = None


@dataclass
class SceneReport:
    title: str
    scene: str                       # the scene's name (its file's stem)
    sweeps: list
    charts: list
    budget: object | None            # budget_table.BudgetTable
    settings: object | None          # settings_plan.SettingsChosen
    timing_path: str | None = None


def chart_title(module):
    return 'whole frame' if module == sweep_data.FRAME else f'{module} module'


def make_chart(points, module, scene, out_dir):
    chart = Chart(module=module, title=chart_title(module))
    if module != sweep_data.FRAME and not any(module in p.module_error for p in points):
        # Frame error would misattribute the other modules' and the engine's error to this one.
        chart.skipped = (f'no point records module_error.{module} (its error against its own ground '
                         f'truth), so there is no {module} error to chart')
        return chart
    measured, chart.notes = sweep_data.measurements(points, module)
    if not measured:
        chart.skipped = 'no point has both a time and a positive error'
        return chart
    front = pareto_front([(m.time_ms, m.error) for m in measured])
    chart.front = [measured[i] for i in front]
    chart.plotted = len(measured)
    time_label = f'ms per frame ({sweep_data.time_basis([m.point for m in measured], module)})'
    chart.png, chart.svg = error_time_chart(measured, front, f'{scene}: {chart.title}', time_label,
                                            str(Path(out_dir) / f'{scene}_{module}'))
    return chart


def build_scene_report(title, scene, sweeps, budget, settings, out_dir, timing_path=None):
    """Draws the scene's charts into out_dir and returns what its HTML page shows."""
    points = [p for s in sweeps for p in s.points]
    keys = [sweep_data.FRAME] + sweep_data.modules(points) if points else []
    charts = [make_chart(points, key, scene, out_dir) for key in keys]
    return SceneReport(title=title, scene=scene, sweeps=sweeps, charts=charts, budget=budget,
                       settings=settings, timing_path=timing_path)
