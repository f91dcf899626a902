"""The report CLI end to end on the fixtures, without a browser: files written, one self-contained page
per scene, the Pareto front, plan and budget table on it (tools/report/cpurender_report.py)."""
import base64
import json
import re
import subprocess
import sys
import tempfile
import unittest
from html.parser import HTMLParser
from pathlib import Path

from report_paths import DATA, TOOLS
from budget_table import budget_table

SCENE = 'fog_valley_flythrough'


class PageParser(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.scripts_with_src = [], [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == 'img':
            self.images.append(attrs.get('src', ''))
        if tag == 'link' or 'href' in attrs:
            self.links.append(attrs)
        if tag == 'script' and 'src' in attrs:
            self.scripts_with_src.append(attrs['src'])


def run_report(out, *args):
    return subprocess.run([sys.executable, str(TOOLS / 'cpurender_report.py'), '--title', 'Fixture',
                           '--out', str(out), *map(str, args)], capture_output=True, text=True, timeout=120)


class FullReportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = Path(cls.tmp.name)
        cls.result = run_report(cls.out, '--sweep', DATA / 'sweep_profiles', '--timing', DATA / 'report.json',
                             '--plan', DATA / 'plan.json')
        cls.html = (cls.out / f'{SCENE}_report.html').read_text() if cls.result.returncode == 0 else ''

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_it_writes_the_page_and_a_png_and_svg_per_chart(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        for key in ('frame', 'atmosphere', 'fog'):
            self.assertTrue((self.out / f'{SCENE}_{key}.png').read_bytes().startswith(b'\x89PNG\r\n\x1a\n'))
            self.assertIn('<svg', (self.out / f'{SCENE}_{key}.svg').read_text())
        self.assertEqual(sorted(p.name for p in self.out.glob('*.html')), [f'{SCENE}_report.html'])

    def test_the_page_is_self_contained(self):
        page = PageParser()
        page.feed(self.html)
        self.assertEqual(len(page.images), 3)
        embedded = {base64.b64decode(src.split(',', 1)[1]) for src in page.images
                    if src.startswith('data:image/png;base64,')}
        charts = {(self.out / f'{SCENE}_{key}.png').read_bytes() for key in ('frame', 'atmosphere', 'fog')}
        self.assertEqual(embedded, charts, 'every image is one of the charts, inline')
        self.assertEqual(page.links, [])
        self.assertEqual(page.scripts_with_src, [])
        self.assertNotRegex(self.html, r'https?://|url\(|@import')

    def test_the_front_tables_list_the_fronts(self):
        sections = re.split(r'<h3>', self.html)
        frame = next(s for s in sections if s.startswith('whole frame'))
        rows = re.findall(r'<tr><td><code>([^<]*)</code></td><td>([^<]*)</td><td class="num">([^<]*)</td>', frame)
        self.assertEqual(rows, [
            ('atmosphere.spectral_samples=3, fog.froxel_size_px=16', 'mobile', '20.00'),
            ('atmosphere.spectral_samples=6, fog.froxel_size_px=16', '', '22.00'),
            ('atmosphere.spectral_samples=6, fog.froxel_size_px=12', 'auto', '23.00'),
            ('atmosphere.spectral_samples=6, fog.froxel_size_px=8', 'desktop', '26.00')])
        self.assertIn('Pareto front (4 of 6 points)', frame)
        self.assertIn('error 0 cannot be drawn on a log axis', frame)

    def test_the_plan_is_shown_with_its_reasons(self):
        self.assertIn('8 px is over the fog share of the budget; 16 px doubles the fog error', self.html)
        self.assertIn('<code>fog.froxel_size_px</code></td><td><code>12</code>', self.html)

    def test_over_budget_cells_are_marked(self):
        table = budget_table(json.loads((DATA / 'report.json').read_text()))
        over = sum(row.over_budget(stat, table.budget_ms) for row in [table.frame] + table.passes
                   for stat in ('p50', 'p95', 'p99', 'amortized_ms'))
        self.assertGreater(over, 0, 'the fixture has over-budget cells')
        self.assertEqual(self.html.count('class="num over"'), over)
        self.assertIn(f'{table.frames_over_budget} of {table.frames} frames over it', self.html)


class PartialInputTest(unittest.TestCase):
    def test_a_sweep_without_module_error_gets_only_the_frame_chart(self):
        with tempfile.TemporaryDirectory() as d:
            run = run_report(d, '--sweep', DATA / 'sweep_froxels')
            self.assertEqual(run.returncode, 0, run.stderr)
            html = (Path(d) / f'{SCENE}_report.html').read_text()
            self.assertEqual(html.count('<img '), 1)
            for module in ('atmosphere', 'fog'):
                self.assertIn(f'No chart: no point records module_error.{module}', html)
                self.assertFalse((Path(d) / f'{SCENE}_{module}.png').exists())
            self.assertIn('No timing report of this scene was given', html)

    def test_a_timing_report_alone(self):
        with tempfile.TemporaryDirectory() as d:
            run = run_report(d, '--timing', DATA / 'report.json')
            self.assertEqual(run.returncode, 0, run.stderr)
            html = (Path(d) / f'{SCENE}_report.html').read_text()
            self.assertNotIn('<img ', html)
            self.assertIn('No sweep of this scene was given', html)
            self.assertIn('<tr class="frame"><td>frame</td>', html)

    def test_bad_input_is_an_error_naming_the_file(self):
        with tempfile.TemporaryDirectory() as d:
            run = run_report(d, '--sweep', DATA / 'no_such_sweep')
            self.assertEqual(run.returncode, 2)
            self.assertIn('no_such_sweep', run.stderr)
            run = run_report(d, '--sweep', DATA / 'sweep_froxels', '--plan', DATA / 'report.json')
            self.assertEqual(run.returncode, 2)
            self.assertIn('without a plan', run.stderr)


if __name__ == '__main__':
    unittest.main()
