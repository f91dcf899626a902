"""One self-contained HTML page per scene: charts embedded as data URIs, inline CSS, nothing fetched.

The page reads without JavaScript. Its one inline script only records, on <body>, how many images
decoded ("data-images-decoded"="N/M"), for the headless-browser test.
"""
import base64
import json
from html import escape
from pathlib import Path

import sweep_data

CSS = """
body { font: 15px/1.45 system-ui, sans-serif; max-width: 60rem; margin: 2rem auto; padding: 0 1rem; color: #222; }
h1 { font-size: 1.6rem; } h2 { margin-top: 2.2rem; border-bottom: 1px solid #ccc; }
.meta, figcaption, .caption { color: #555; font-size: 0.9rem; }
figure { margin: 1.2rem 0; } figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
table { border-collapse: collapse; margin: 0.6rem 0; font-size: 0.9rem; }
th, td { border: 1px solid #ccc; padding: 0.2rem 0.5rem; text-align: left; vertical-align: top; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.frame td { font-weight: bold; background: #f4f4f4; }
td.over { background: #fbd5d5; color: #8a0000; font-weight: bold; }
.notes { color: #555; font-size: 0.9rem; }
code { font-size: 0.9em; }
"""

# Counts decoded images after load; the browser test reads the attribute from the dumped DOM.
CHECK_IMAGES_JS = """
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var decoded = images.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  document.body.setAttribute('data-images-decoded', decoded + '/' + images.length);
});
"""

OVER_MARK = '\u25b2'  # next to an over-budget value, so the table reads without colour too


def _ms(value):
    return f'{value:.2f}'


def _data_uri(png_path):
    return 'data:image/png;base64,' + base64.b64encode(Path(png_path).read_bytes()).decode('ascii')


def _settings_text(settings):
    return ', '.join(f'{k}={v if isinstance(v, str) else json.dumps(v)}' for k, v in settings.items())


def _notes(items):
    return '<ul class="notes">' + ''.join(f'<li>{escape(i)}</li>' for i in items) + '</ul>'


def _error_meaning(module):
    if module == sweep_data.FRAME:
        return 'error of the last frame against the sweep\'s reference render'
    return f'error of the {module} module against its own ground truth (module_error.{module})'


def _front_table(chart, merged):
    head = '<tr>' + ('<th>sweep</th>' if merged else '') + \
        '<th>point</th><th>label</th><th class="num">ms per frame</th><th class="num">error</th></tr>'
    rows = []
    for m in chart.front:
        p = m.point
        rows.append('<tr>' + (f'<td>{escape(p.source)}</td>' if merged else '') +
                    f'<td><code>{escape(_settings_text(p.settings) or p.id)}</code></td>'
                    f'<td>{escape(p.label or "")}</td><td class="num">{_ms(m.time_ms)}</td>'
                    f'<td class="num">{m.error:.4g}</td></tr>')
    return f'<table><caption class="caption">Pareto front ({len(chart.front)} of {chart.plotted} ' \
           f'points)</caption>{head}{"".join(rows)}</table>'


def _charts_section(report):
    out = ['<section id="charts"><h2>Error against time</h2>']
    if not report.charts:
        out.append('<p class="notes">No sweep of this scene was given (--sweep), so there are no charts.</p>')
    else:
        out.append('<p>Each grey dot is a sweep point: its ms per frame (x) against its mean relative '
                   'luminance error (y, log scale). The black step line is the Pareto front: the points '
                   'no other point matches in both time and error while beating them in one. Named '
                   'profiles have their own markers.</p>')
    merged = len(report.sweeps) > 1
    for chart in report.charts:
        out.append(f'<h3>{escape(chart.title)}</h3>')
        if chart.skipped:
            out.append(f'<p class="notes">No chart: {escape(chart.skipped)}.</p>')
            continue
        out.append(f'<figure><img src="{_data_uri(chart.png)}" alt="{escape(report.scene)}: '
                   f'{escape(chart.title)}, error against time with the Pareto front">'
                   f'<figcaption>{escape(chart.title)}: {escape(_error_meaning(chart.module))}. '
                   f'Also as {escape(Path(chart.png).name)} and '
                   f'{escape(Path(chart.svg).name)}.</figcaption></figure>')
        out.append(_front_table(chart, merged))
        if chart.notes:
            out.append('<p class="notes">Not drawn:</p>' + _notes(chart.notes))
    out.append('</section>')
    return ''.join(out)


def _settings_section(settings):
    out = ['<section id="settings"><h2>Settings chosen</h2>']
    if settings is None:
        out.append('<p class="notes">No plan or profile was given (--plan), and the timing report has '
                   'no plan.</p></section>')
        return ''.join(out)
    what = 'The plan' if settings.kind == 'plan' else 'The profile'
    out.append(f'<p class="caption">{what} from <code>{escape(settings.source)}</code>.</p>')
    if settings.details:
        out.append('<table>' + ''.join(f'<tr><th>{escape(k)}</th><td><code>{escape(v)}</code></td></tr>'
                                       for k, v in settings.details) + '</table>')
    head = '<tr><th>key</th><th>value</th>' + ('<th>reason</th>' if settings.kind == 'plan' else '') + '</tr>'
    rows = ''.join(f'<tr><td><code>{escape(k)}</code></td><td><code>{escape(v)}</code></td>' +
                   (f'<td>{escape(r)}</td>' if settings.kind == 'plan' else '') + '</tr>'
                   for k, v, r in settings.rows)
    out.append(f'<table>{head}{rows}</table>' if settings.rows else '<p class="notes">The plan has no choices.</p>')
    out.append('</section>')
    return ''.join(out)


def _budget_cell(row, stat, budget_ms):
    value = getattr(row, stat)
    if row.over_budget(stat, budget_ms):
        return f'<td class="num over" title="over the {_ms(budget_ms)} ms budget">{_ms(value)} {OVER_MARK}</td>'
    return f'<td class="num">{_ms(value)}</td>'


def _budget_section(budget, timing_path):
    out = ['<section id="budget"><h2>Frame budget</h2>']
    if budget is None:
        out.append('<p class="notes">No timing report of this scene was given (--timing).</p></section>')
        return ''.join(out)
    if budget.budget_ms > 0:
        out.append(f'<p>Budget <b>{_ms(budget.budget_ms)} ms</b> per frame; {budget.frames_over_budget} of {budget.frames} '
                   f'frames over it. Cells over the budget are marked {OVER_MARK}.</p>')
    else:
        out.append('<p class="notes">The profile sets no frame budget: nothing is marked.</p>')
    out.append(f'<p class="caption">From <code>{escape(str(timing_path))}</code>: {budget.frames} measured '
               f'frames, {budget.threads} threads, profile <code>{escape(budget.profile)}</code>. '
               'Percentiles are nearest-rank over the frames a pass ran in; the amortised mean spreads '
               'a pass\'s total time over every frame. Passes by amortised mean, largest first.</p>')
    head = ('<tr><th>pass</th><th class="num">frames run</th><th class="num">p50 ms</th>'
            '<th class="num">p95 ms</th><th class="num">p99 ms</th><th class="num">amortised ms</th></tr>')
    rows = []
    for row in [budget.frame] + sorted(budget.passes, key=lambda r: -r.amortized_ms):
        css = ' class="frame"' if row is budget.frame else ''
        rows.append(f'<tr{css}><td>{escape(row.name)}</td><td class="num">{row.frames_run}</td>' +
                    ''.join(_budget_cell(row, s, budget.budget_ms) for s in ('p50', 'p95', 'p99', 'amortized_ms')) +
                    '</tr>')
    out.append(f'<table>{head}{"".join(rows)}</table></section>')
    return ''.join(out)


def render_html(report):
    sources = [str(s.path) for s in report.sweeps]
    points = sum(len(s.points) for s in report.sweeps)
    meta = (f'Sweeps: {", ".join(sources)} ({points} points).' if sources else 'No sweeps.') + \
        (f' Timing: {report.timing_path}.' if report.timing_path else '')
    page_title = f'{report.title}: {report.scene}'
    return ('<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f'<title>{escape(page_title)}</title><style>{CSS}</style></head>\n<body>'
            f'<h1>{escape(page_title)}</h1><p class="meta">{escape(meta)}</p>'
            f'{_charts_section(report)}{_settings_section(report.settings)}'
            f'{_budget_section(report.budget, report.timing_path)}'
            f'<script>{CHECK_IMAGES_JS}</script></body></html>\n')


def write_html(report, out_dir):
    path = Path(out_dir) / f'{report.scene}_report.html'
    path.write_text(render_html(report), encoding='utf-8')
    return path

