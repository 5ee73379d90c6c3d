#!/usr/bin/env python3
"""scripts/tune.py as `make tune ROBOT=eurobot2009 TRIALS=2 SEEDS=1` runs it (launch/tune_smoke.test),
on a local cluster of two workers, with 30 s matches (--match-duration: the machinery, not the
robot, is under test) and one held-out seed per side (the interval then reads nan; the paired t
itself is test/unit/test_tune.py's). The runner exits 0 and its last line is
    trials 2 best_score B baseline_score S improvement D ci95 [L, H]
with D = B - S; the study is in its storage with 2 finished trials, the first being the shipped
config's values; the best overlay parses and holds every declared parameter; the PNG exists. A
second run on the same storage with --trials 2 plays no new trial (the study resumes)."""
import math
import os
import re
import shutil
import sys
import tempfile
import unittest

import rostest
import yaml

from match_runner import run_runner  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.tuning import tune

ROBOT = 'eurobot2009'
CLOSING = re.compile(r'^trials (?P<t>\d+) best_score (?P<b>\S+) baseline_score (?P<s>\S+) improvement (?P<d>\S+) '
                     r'ci95 \[(?P<low>\S+), (?P<high>\S+)\]$')
RUNNER_TIMEOUT = 1000.0


class TuneSmokeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = tempfile.mkdtemp(prefix='tune_smoke_')
        # The study's options; the verdict's held-out seeds are added per run.
        cls.study = [sys.executable, os.path.join(ROOT, 'scripts', 'tune.py'), ROBOT, '--trials', '2', '--seeds', '1',
                     '--workers', '2', '--match-duration', '30', '--out', cls.out]
        cls.cmd = cls.study + ['--holdout', '1']
        cls.rc, cls.output = run_runner(cls.cmd, RUNNER_TIMEOUT)
        print(cls.output, flush=True)

    @classmethod
    def tearDownClass(cls):
        if cls.rc == 0:
            shutil.rmtree(cls.out, ignore_errors=True)

    def test_1_closing_line(self):
        self.assertEqual(self.rc, 0, self.output[-3000:])
        m = CLOSING.match(self.output.strip().splitlines()[-1])
        self.assertIsNotNone(m, self.output[-2000:])
        self.assertEqual(int(m.group('t')), 2)
        b, s, d = float(m.group('b')), float(m.group('s')), float(m.group('d'))
        self.assertAlmostEqual(d, b - s, places=2)
        low, high = float(m.group('low')), float(m.group('high'))
        self.assertTrue(math.isnan(low) or low <= d <= high, (low, d, high))

    def test_2_the_study_is_stored_with_the_shipped_config_first(self):
        import optuna
        study = optuna.load_study(study_name=ROBOT, storage='sqlite:///' + os.path.join(self.out, ROBOT + '_study.db'))
        done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
        self.assertEqual(len(done), 2)
        params, _ = tune.load_space(ROBOT)
        self.assertEqual(study.trials[0].params, tune.shipped_point(params, tune.match_config.robot_config(ROBOT)))

    def test_3_best_overlay_and_figure(self):
        with open(os.path.join(self.out, ROBOT + '_best.yaml')) as f:
            best = yaml.safe_load(f)
        params, _ = tune.load_space(ROBOT)
        for p in params:
            self.assertIsNot(tune.lookup(best, p['name']), KeyError, p['name'])
        self.assertGreater(os.path.getsize(os.path.join(self.out, ROBOT + '_tune.png')), 10000)

    def test_4_a_finished_study_resumes_without_new_trials(self):
        rc, output = run_runner(self.study + ['--holdout', '0'], 400.0)
        self.assertEqual(rc, 0, output[-2000:])
        self.assertIn('2 finished trial(s), 0 to go', output)
        self.assertNotIn('tune: trial ', output)
        self.assertIn('no verdict (--holdout 0)', output)
        self.assertRegex(output.strip().splitlines()[-1], r'^trials 2 best_score nan baseline_score nan ')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'tune_smoke', TuneSmokeTest, sys.argv)
