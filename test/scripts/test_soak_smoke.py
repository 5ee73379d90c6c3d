#!/usr/bin/env python3
"""scripts/soak.py as `make soak N=1` runs it (test/launch/soak_smoke.test): one match without
faults, one with them, 30 s each: the summary has its lines (violations by class, false alarms,
worst recovery per fault class, scores with and without faults) and the closing line parses,
`soak eurobot2009 matches 1 chaos 1 violations V`."""
import os
import re
import shutil
import sys
import tempfile
import unittest

import rospy
import rostest

from match_runner import run_runner  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
ROBOT = 'eurobot2009'
CLOSING = re.compile(r'^soak (?P<robot>\S+) matches (?P<m>\d+) chaos (?P<c>\d+) violations (?P<v>\d+)$')


class SoakSmokeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_soak_smoke')
        cls.out = tempfile.mkdtemp(prefix='soak_smoke_')
        cmd = [sys.executable, os.path.join(ROOT, 'scripts', 'soak.py'), ROBOT, '--n', '1', '--seed', '1',
               '--factor', repr(float(rospy.get_param('~factor', 0.0))), '--out', cls.out, '--match-duration', '30']
        cls.rc, cls.output = run_runner(cmd, 800.0)
        print(cls.output)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_closing_line_parses(self):
        lines = self.output.strip().splitlines()
        m = CLOSING.match(lines[-1])
        self.assertIsNotNone(m, 'closing line: %r' % lines[-1])
        self.assertEqual((m.group('robot'), m.group('m'), m.group('c')), (ROBOT, '1', '1'))
        self.assertEqual(self.rc, 1 if int(m.group('v')) else 0, 'exit code against the violations')

    def test_summary_has_its_lines(self):
        with open(os.path.join(self.out, '%s_soak.txt' % ROBOT)) as f:
            text = f.read()
        for start in ('violations by class:', 'false alarms:', 'worst recovery per fault class',
                      'score ours:'):
            self.assertIn('\n' + start, '\n' + text, text)
        self.assertTrue(os.path.isdir(os.path.join(self.out, 'matches')))
        self.assertTrue(os.path.isdir(os.path.join(self.out, 'chaos')))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'soak_smoke', SoakSmokeTest, sys.argv)
