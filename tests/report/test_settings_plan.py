"""The "settings chosen" section's data: a plan or a profile (tools/report/settings_plan.py)."""
import json
import tempfile
import unittest
from pathlib import Path

from report_paths import DATA, REPO
from settings_plan import PlanError, find_plan, load_settings


class SettingsTest(unittest.TestCase):
    def test_a_plan_file(self):
        settings = load_settings(DATA / 'plan.json')
        self.assertEqual(settings.kind, 'plan')
        self.assertEqual(settings.rows[0], ('atmosphere.spectral_samples', '6',
                                            'the cheapest count on the atmosphere front within 0.02 error'))
        self.assertEqual(settings.rows[2][:2], ('antialiasing', 'msaa4'))   # a string value, unquoted
        self.assertEqual(settings.details, [('profile', 'auto'), ('frame_budget_ms', '33.3')])

    def test_the_plan_of_a_render_report(self):
        plan = {'choices': [{'key': 'fog.slices', 'value': 32, 'reason': 'r'}]}
        self.assertIs(find_plan({'format': 'cpurender-run-report', 'plan': plan}), plan)
        self.assertIs(find_plan({'extra': {'plan': plan}}), plan)
        self.assertIsNone(find_plan(json.loads((DATA / 'report.json').read_text())))

    def test_a_profile_is_shown_as_its_dotted_keys(self):
        settings = load_settings(REPO / 'profiles' / 'mobile.json')
        self.assertEqual(settings.kind, 'profile')
        rows = {k: v for k, v, _ in settings.rows}
        self.assertEqual(rows['atmosphere.skyview_lut.width'], '96')
        self.assertEqual(rows['resolution'], '[960, 540]')
        self.assertEqual(rows['fog.precision'], 'fixed')
        self.assertTrue(all(reason == '' for _, _, reason in settings.rows))

    def test_a_render_report_without_a_plan_is_refused(self):
        with self.assertRaisesRegex(PlanError, 'without a plan'):
            load_settings(DATA / 'report.json')

    def test_malformed_plans(self):
        for doc in ({'choices': {}}, {'choices': [{'value': 1}]}, [1, 2]):
            with self.subTest(doc), tempfile.TemporaryDirectory() as d:
                path = Path(d) / 'plan.json'
                path.write_text(json.dumps(doc))
                with self.assertRaises(PlanError):
                    load_settings(path)


if __name__ == '__main__':
    unittest.main()
