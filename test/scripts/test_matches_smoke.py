#!/usr/bin/env python3
"""scripts/run_matches.py as `make matches N=2 WORKERS=2` runs it (launch/matches_smoke.test):
eurobot2009, seeds 1 and 2, 30 s matches at the test's ~factor (default 1.0), on a local Dask cluster of two
workers, so both matches run at once, each on its own ROS master and ports. The runner exits 0,
both matches ended (run_match.py said so and kept a bag and a report in each match folder), the
summary says 2 workers and no retry, the summary PNG is written, the results against each opponent
and in all (`wins W losses L draws D`) come before the closing line, which parses with 2 matches
and 0 violations. And the recorder kept what is read afterwards: every topic the match report,
the runner's row and the chaos invariants look for is in each match's (LZ4-compressed) bag."""
import math
import os
import re
import shutil
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest

from match_runner import run_runner  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
ROBOT, N, SEED = 'eurobot2009', 2, 1
CLOSING = re.compile(r'^matches (?P<n>\d+) score_mean (?P<mean>\S+) score_min (?P<min>\S+) '
                     r'violations (?P<violations>\d+) wall_s (?P<wall>\S+) factor (?P<factor>\S+)$')
RUNNER_TIMEOUT = 1100.0  # [s, wall]: below the test's time-limit, so a hang fails here with the output


def recorder_selection():
    """(topics, exclude): the full-match regular expressions rosbag record gets from
    launch/include/record.launch.xml (image topics excluded, as by default)."""
    root = ET.parse(os.path.join(ROOT, 'launch', 'include', 'record.launch.xml')).getroot()
    args = {a.get('name'): a.get('value') for a in root.iter('arg') if a.get('value') is not None}
    exclude = re.sub(r'\$\(arg (\w+)\)', lambda m: args[m.group(1)], args['exclude'])
    return args['topics'], exclude


class MatchesSmokeTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_matches_smoke')
        cls.factor = float(rospy.get_param('~factor', 1.0))
        cls.out = tempfile.mkdtemp(prefix='matches_smoke_')
        cmd = [sys.executable, os.path.join(ROOT, 'scripts', 'run_matches.py'), ROBOT, '--n', str(N),
               '--seed', str(SEED), '--factor', repr(cls.factor), '--out', cls.out, '--workers', '2',
               '--match-duration', '30']  # the runner end to end: a 30 s match is one as much as a 90 s one
        cls.rc, cls.output = run_runner(cmd, RUNNER_TIMEOUT)
        print(cls.output)  # the runner's progress and table in the test's log

    @classmethod
    def tearDownClass(cls):
        if cls.rc == 0:
            shutil.rmtree(cls.out, ignore_errors=True)  # ~130 MB of bags; kept for a look when it failed

    def closing(self):
        lines = self.output.strip().splitlines()
        self.assertTrue(lines, 'no output')
        m = CLOSING.match(lines[-1])
        self.assertIsNotNone(m, 'closing line: %r' % lines[-1])
        return m

    def test_runner_exits_zero(self):
        self.assertEqual(self.rc, 0, self.output[-3000:])

    def test_two_workers_no_retry(self):
        self.assertIn('cluster: 2 workers, 0 retries', self.output.splitlines(), self.output[-3000:])

    def test_closing_line_parses_without_violations(self):
        m = self.closing()
        self.assertEqual(int(m.group('n')), N)
        self.assertEqual(int(m.group('violations')), 0, self.output[-3000:])
        self.assertAlmostEqual(float(m.group('factor')), self.factor)
        self.assertGreater(float(m.group('wall')), 0.0)
        self.assertFalse(math.isnan(float(m.group('mean'))), 'no match has a score')
        self.assertFalse(math.isnan(float(m.group('min'))))
        self.assertNotIn('violation:', self.output)

    def test_both_matches_ended_with_bag_and_report(self):
        for seed in range(SEED, SEED + N):
            folder = os.path.join(self.out, '%s_seed%d' % (ROBOT, seed))
            with open(os.path.join(folder, 'run_match.out')) as f:
                said = f.read()
            self.assertIn('run: match ended', said, 'seed %d: %s' % (seed, said[-2000:]))
            for name in ('_match.bag', '_match.png', '_launch.log'):
                self.assertTrue(os.path.exists(os.path.join(folder, ROBOT + name)), 'seed %d: no %s' % (seed, name))
            self.assertTrue(os.path.exists(os.path.join(folder, 'overlay.yaml')))
        self.assertTrue(os.path.exists(os.path.join(self.out, ROBOT + '_matches.png')))

    def test_results_line_before_the_closing_line(self):
        lines = self.output.strip().splitlines()
        m = re.match(r'^wins (\d+) losses (\d+) draws (\d+)$', lines[-2])
        self.assertIsNotNone(m, 'line before the closing line: %r' % lines[-2])
        self.assertEqual(sum(int(g) for g in m.groups()), N)
        for kind in ('random_walk', 'route'):
            self.assertTrue(any(re.match(r'^opponent %s: wins \d+ losses \d+ draws \d+ win_rate \S+$' % kind, l)
                                for l in lines), 'no results line for %s' % kind)

    def test_bags_hold_every_topic_the_readers_look_for(self):
        from robot_tools.report import match_bag, match_report
        from robot_tools.chaos import run_chaos
        from robot_tools.matches import match_config
        from robot_tools.matches import match_rows
        import rosbag
        config = match_config.robot_config(ROBOT)
        topics, exclude = recorder_selection()
        asked = set()
        opened = match_bag.Match.__init__

        def opened_and_watched(match, *args, **kwargs):  # every Match shares one record of what was asked
            opened(match, *args, **kwargs)
            match.asked = asked
        match_bag.Match.__init__ = opened_and_watched
        try:
            for seed in range(SEED, SEED + N):
                folder = os.path.join(self.out, '%s_seed%d' % (ROBOT, seed))
                bag = os.path.join(folder, ROBOT + '_match.bag')
                asked.clear()
                match_rows.analyse(seed, 'random_walk', folder, ROBOT, config, 0, 0.0)
                run_chaos.judge(folder, ROBOT, config, 0)
                match_report.report(bag, os.path.join(self.out, 'asked.png'))
                # What the readers look for is what the recorder keeps (a topic published only on an
                # event, a goal's result, may be absent from one match; a pattern `prefix*word` too) ...
                exact = {t for t in asked if '*' not in t}
                self.assertIn('/mcl/pose', exact)
                self.assertIn('/diagnostics', exact)
                dropped = sorted(t for t in exact if not re.fullmatch(topics, t) or re.fullmatch(exclude, t))
                self.assertEqual(dropped, [], 'seed %d: read afterwards, but the recorder leaves them out' % seed)
                # ... and the streams every match has are in the bag, compressed.
                with rosbag.Bag(bag) as b:
                    recorded = set(b.get_type_and_topic_info().topics)
                    compressed = {c.compression for c in b._chunk_headers.values()}
                for topic in ('/mcl/pose', '/diagnostics', '/odom', '/sim/ground_truth', '/sim/opponent', '/sim/match',
                              '/hal/drive/cmd_vel', '/hcl/motor_board/motor/left/command', '/rosout'):
                    self.assertIn(topic, recorded, 'seed %d' % seed)
                self.assertEqual(compressed, {'lz4'}, 'seed %d' % seed)
        finally:
            match_bag.Match.__init__ = opened

    def test_one_row_per_match(self):
        rows = [l for l in self.output.splitlines() if re.match(r'^\s*\d+ (random_walk|route|blocker) ', l)]
        self.assertEqual([int(r.split()[0]) for r in rows], list(range(SEED, SEED + N)), self.output[-3000:])
        self.assertEqual([r.split()[1] for r in rows], ['random_walk', 'route'])


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'matches_smoke', MatchesSmokeTest, sys.argv)
