"""The frame-budget table of a timing report (tools/report/budget_table.py)."""
import json
import unittest

from report_paths import DATA
from budget_table import TimingError, budget_table, percentile_nearest_rank


def frame(ms, passes):
    return {'frame_ms': ms, 'passes': [{'name': n, 'ms': v} for n, v in passes]}


# Four frames against a 25 ms budget; the sky-view LUT runs in two of them.
HAND_MADE = {
    'scene': 'scenes/fog_valley_flythrough.json', 'profile': 'profiles/desktop.json', 'threads': 2,
    'summary': {'frame_budget_ms': 25.0},
    'frames': [frame(10, [('geometry', 1), ('atmosphere.skyview', 8)]),
               frame(40, [('geometry', 4)]),
               frame(20, [('geometry', 2), ('atmosphere.skyview', 6)]),
               frame(30, [('geometry', 3)])],
}


class PercentileTest(unittest.TestCase):
    def test_nearest_rank(self):
        self.assertEqual(percentile_nearest_rank([40, 10, 30, 20], 50), 20)   # rank ceil(2) = 2
        self.assertEqual(percentile_nearest_rank([40, 10, 30, 20], 95), 40)   # rank ceil(3.8) = 4
        self.assertEqual(percentile_nearest_rank([40, 10, 30, 20], 0), 10)    # rank at least 1
        self.assertEqual(percentile_nearest_rank([], 50), 0.0)

    def test_p95_of_100_samples_is_rank_95_despite_binary_rounding(self):
        self.assertEqual(percentile_nearest_rank(list(range(1, 101)), 95), 95)
        self.assertEqual(percentile_nearest_rank(list(range(1, 101)), 99), 99)


class HandMadeTableTest(unittest.TestCase):
    def setUp(self):
        self.table = budget_table(HAND_MADE)

    def test_frame_row(self):
        row = self.table.frame
        self.assertEqual((row.frames_run, row.p50, row.p95, row.p99, row.amortized_ms), (4, 20, 40, 40, 25))
        self.assertEqual(self.table.budget_ms, 25.0)
        self.assertEqual(self.table.frames_over_budget, 2)   # 30 and 40 ms

    def test_pass_rows_in_order_of_first_appearance(self):
        self.assertEqual([r.name for r in self.table.passes], ['geometry', 'atmosphere.skyview'])
        geometry, skyview = self.table.passes
        self.assertEqual((geometry.p50, geometry.p95, geometry.p99, geometry.amortized_ms), (2, 4, 4, 2.5))
        # Percentiles over the two frames it ran in; its amortised time over all four.
        self.assertEqual((skyview.frames_run, skyview.p50, skyview.p95, skyview.amortized_ms), (2, 6, 8, 3.5))

    def test_over_budget_cells(self):
        row = self.table.frame
        self.assertEqual([row.over_budget(s, 25.0) for s in ('p50', 'p95', 'p99', 'amortized_ms')],
                         [False, True, True, False])   # 25 ms is within a 25 ms budget
        self.assertFalse(row.over_budget('p99', 0.0), 'no budget, nothing over')

    def test_no_budget(self):
        table = budget_table(dict(HAND_MADE, summary={'frame_budget_ms': 0}))
        self.assertEqual((table.budget_ms, table.frames_over_budget), (0.0, 0))

    def test_a_report_without_frames_is_refused(self):
        for report in ({'summary': {}}, dict(HAND_MADE, frames=[{'frame_ms': 3}])):
            with self.assertRaises(TimingError):
                budget_table(report)


class EngineReportTest(unittest.TestCase):
    """The table of a real `cpurender render` report agrees with the engine's own summary."""

    def setUp(self):
        self.report = json.loads((DATA / 'report.json').read_text())
        self.table = budget_table(self.report)

    def test_frame_percentiles_match_the_summary(self):
        frame_ms = self.report['summary']['frame_ms']
        self.assertEqual(self.table.frames, self.report['summary']['frames'])
        for stat in ('p50', 'p95', 'p99'):
            self.assertEqual(getattr(self.table.frame, stat), frame_ms[stat], stat)
        self.assertAlmostEqual(self.table.frame.amortized_ms, frame_ms['mean'], places=9)
        self.assertEqual(self.table.frames_over_budget, self.report['summary']['frames_over_budget'])

    def test_pass_percentiles_match_the_summary(self):
        summary = {p['name']: p for p in self.report['summary']['passes']}
        self.assertEqual({r.name for r in self.table.passes}, set(summary))
        for row in self.table.passes:
            expected = summary[row.name]
            self.assertEqual(row.frames_run, expected['frames_run'], row.name)
            self.assertEqual((row.p50, row.p95), (expected['p50'], expected['p95']), row.name)
            self.assertAlmostEqual(row.amortized_ms, expected['amortized_ms'], places=9, msg=row.name)
            self.assertGreaterEqual(row.p99, row.p95, row.name)


if __name__ == '__main__':
    unittest.main()
