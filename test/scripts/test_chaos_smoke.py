#!/usr/bin/env python3
"""scripts/run_chaos.py as `make chaos` runs it, with N=2 and the fixed schedule
test/config/chaos_eurobot2009.yaml (every fault class of the 2009 robot: its buses, the world,
its processes killed and stalled; launch/chaos_smoke.test): the runner exits 0, every scheduled
fault was injected (each match's faults.yaml), the closing line parses with 2 matches, 15
faults and 0 violations, and each match kept a readable bag and its report."""
import os
import re
import shutil
import sys
import tempfile
import unittest

import rospy
import rostest
import yaml

from match_runner import run_runner  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
ROBOT, N, SEED = 'eurobot2009', 2, 1
SCHEDULE = os.path.join(ROOT, 'test', 'config', 'chaos_eurobot2009.yaml')
CLOSING = re.compile(r'^matches (?P<n>\d+) faults (?P<faults>\d+) violations (?P<violations>\d+)$')
RUNNER_TIMEOUT = 1100.0  # [s, wall]: below the test's time-limit, so a hang fails here with the output


class ChaosSmokeTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_chaos_smoke')
        cls.factor = float(rospy.get_param('~factor', 0.0))
        cls.out = tempfile.mkdtemp(prefix='chaos_smoke_')
        with open(SCHEDULE) as f:
            cls.schedule = yaml.safe_load(f)
        cmd = [sys.executable, os.path.join(ROOT, 'scripts', 'run_chaos.py'), ROBOT, '--n', str(N), '--seed', str(SEED),
               '--factor', repr(cls.factor), '--out', cls.out, '--schedule', SCHEDULE]
        cls.rc, cls.output = run_runner(cmd, RUNNER_TIMEOUT)
        print(cls.output)

    @classmethod
    def tearDownClass(cls):
        if cls.rc == 0:
            shutil.rmtree(cls.out, ignore_errors=True)  # bags; kept for a look when it failed

    def test_every_fault_class_of_the_robot_is_scheduled(self):
        from robot_tools.chaos import faults as chaos_faults
        from robot_tools.matches import match_config
        classes = set(chaos_faults.catalogue(match_config.robot_config(ROBOT)))
        scheduled = {f['class'] for match in self.schedule for f in match}
        self.assertEqual(classes - scheduled, set(), 'fault classes the schedule misses')

    def test_runner_exits_zero_without_violations(self):
        self.assertEqual(self.rc, 0, self.output[-4000:])
        self.assertNotIn('violation:', self.output)
        m = CLOSING.match(self.output.strip().splitlines()[-1])
        self.assertIsNotNone(m, 'closing line: %r' % self.output.strip().splitlines()[-1:])
        self.assertEqual(int(m.group('n')), N)
        self.assertEqual(int(m.group('faults')), sum(len(s) for s in self.schedule[:N]))
        self.assertEqual(int(m.group('violations')), 0)

    def test_every_fault_was_injected_and_each_match_kept_its_bag(self):
        for k, seed in enumerate(range(SEED, SEED + N)):
            folder = os.path.join(self.out, '%s_seed%d' % (ROBOT, seed))
            with open(os.path.join(folder, 'faults.yaml')) as f:
                done = yaml.safe_load(f) or []
            self.assertEqual(sorted(d['class'] for d in done), sorted(f['class'] for f in self.schedule[k]))
            for d in done:
                self.assertFalse(d['outcome'].startswith(('REFUSED', 'FAILED')), d)
                self.assertNotIn('NOT back', d['outcome'])
            for name in (ROBOT + '_match.bag', ROBOT + '_match.png'):
                self.assertTrue(os.path.exists(os.path.join(folder, name)), '%s missing in %s' % (name, folder))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_chaos_smoke', ChaosSmokeTest)
