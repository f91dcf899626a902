"""Loading sweep.json and reading module time and error per point (tools/report/sweep_data.py)."""
import json
import tempfile
import unittest
from pathlib import Path

from report_paths import DATA
import sweep_data
from sweep_data import FRAME, SweepError, load_sweep


class LoadTest(unittest.TestCase):
    def test_a_sweep_with_the_optional_fields(self):
        sweep = load_sweep(DATA / 'sweep_profiles')
        self.assertEqual(sweep.scene_name, 'fog_valley_flythrough')
        self.assertEqual(len(sweep.points), 8)
        self.assertEqual([p.label for p in sweep.points if p.label], ['mobile', 'desktop', 'auto'])
        self.assertEqual(sweep.points[0].source, 'sweep_profiles')
        self.assertEqual(sweep_data.modules(sweep.points), ['atmosphere', 'fog'])

    def test_a_sweep_without_them_as_the_sweep_command_writes_it(self):
        sweep = load_sweep(DATA / 'sweep_froxels' / 'sweep.json')
        self.assertEqual(len(sweep.points), 4)
        self.assertTrue(all(p.label is None and p.module_error == {} for p in sweep.points))
        self.assertEqual(sweep.points[0].id, 'antialiasing=none;fog.froxel_size_px=8')
        self.assertEqual(sweep.points[0].settings, {'antialiasing': 'none', 'fog.froxel_size_px': 8})

    def _load(self, doc):
        with tempfile.TemporaryDirectory() as d:
            (Path(d) / 'sweep.json').write_text(doc if isinstance(doc, str) else json.dumps(doc))
            return load_sweep(d)

    def test_malformed_files_name_the_field(self):
        good = json.loads((DATA / 'sweep_froxels' / 'sweep.json').read_text())
        cases = {
            'not json': ('{', 'sweep.json'),
            'no scene': ({'points': []}, '"scene"'),
            'no frame time': (self._without(good, 'frame_ms_p50'), '"frame_ms_p50"'),
            'no pass p95': (self._without_pass_stat(good, 'p95'), '"p95"'),
            'a string time': (self._with(good, 'frame_ms_p95', '12'), 'frame_ms_p95'),
        }
        for name, (doc, message) in cases.items():
            with self.subTest(name), self.assertRaisesRegex(SweepError, message):
                self._load(doc)

    def test_missing_file(self):
        with self.assertRaises(SweepError):
            load_sweep(DATA / 'no_such_sweep')

    @staticmethod
    def _without(doc, key):
        doc = json.loads(json.dumps(doc))
        del doc['points'][1][key]
        return doc

    @staticmethod
    def _with(doc, key, value):
        doc = json.loads(json.dumps(doc))
        doc['points'][0][key] = value
        return doc

    @staticmethod
    def _without_pass_stat(doc, stat):
        doc = json.loads(json.dumps(doc))
        del doc['points'][0]['passes']['shade'][stat]
        return doc


class TimeAndErrorTest(unittest.TestCase):
    def setUp(self):
        self.profiles = load_sweep(DATA / 'sweep_profiles').points
        self.froxels = load_sweep(DATA / 'sweep_froxels').points

    def test_module_of_a_pass(self):
        self.assertEqual(sweep_data.module_of('atmosphere.skyview'), 'atmosphere')
        self.assertEqual(sweep_data.module_of('fog.lighting'), 'fog')
        self.assertIsNone(sweep_data.module_of('shade'))
        self.assertIsNone(sweep_data.module_of('view distance'))

    def test_module_time_prefers_the_amortised_mean(self):
        mobile = self.profiles[0]
        # Its LUT passes' p50 is 0 (most frames skip them); their means are 1.0 and 0.5 ms.
        self.assertEqual(mobile.passes['atmosphere.skyview']['p50'], 0.0)
        self.assertAlmostEqual(sweep_data.time_ms(mobile, 'atmosphere'), 1.5)
        self.assertAlmostEqual(sweep_data.time_ms(mobile, 'fog'), 3.0)
        self.assertEqual(sweep_data.time_ms(mobile, FRAME), 20.0)
        self.assertEqual(sweep_data.time_basis(self.profiles, 'fog'), "sum of passes' amortised means")

    def test_module_time_without_means_sums_the_p50s(self):
        point = self.froxels[0]
        atmosphere_p50 = 0.07632500000001165 + 0.004277000000001863 + 21.269640000000013  # from the file
        self.assertAlmostEqual(sweep_data.time_ms(point, 'atmosphere'), atmosphere_p50, places=12)
        self.assertEqual(sweep_data.time_basis(self.froxels, 'atmosphere'), "sum of passes' p50")
        self.assertEqual(sweep_data.time_basis(self.froxels + self.profiles, 'atmosphere'),
                         "sum of passes' amortised means, p50 where absent")
        self.assertIsNone(sweep_data.time_ms(point, 'clouds'))

    def test_error_of_the_frame_and_of_a_module(self):
        desktop = self.profiles[3]
        self.assertEqual(desktop.label, 'desktop')
        self.assertEqual(sweep_data.error(desktop, FRAME), 0.020)
        self.assertEqual(sweep_data.error(desktop, 'atmosphere'), 0.020)
        self.assertEqual(sweep_data.error(desktop, 'fog'), 0.010)
        # Without module_error there is no module error: the frame's is not used in its place.
        self.assertIsNone(sweep_data.error(self.froxels[0], 'fog'))
        self.assertAlmostEqual(sweep_data.error(self.froxels[0], FRAME), 0.010671483131073316)

    def test_zero_and_missing_errors_are_left_out_with_a_note(self):
        measured, notes = sweep_data.measurements(self.profiles, FRAME)
        self.assertEqual(len(measured), 6)
        self.assertEqual(notes, ['atmosphere.spectral_samples=9;fog.froxel_size_px=8: error 0 cannot be drawn '
                                 'on a log axis', 'resolution=160x90: no error recorded'])
        measured, notes = sweep_data.measurements(self.profiles, 'fog')
        self.assertEqual(len(measured), 7)
        self.assertEqual(notes, ['resolution=160x90: no error recorded'])


if __name__ == '__main__':
    unittest.main()
