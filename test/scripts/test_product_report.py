#!/usr/bin/env python3
"""scripts/match_report.py on bags whose content is known: the figures in its summary are
the right ones (localization RMS/max error against the truth, score, ERROR lines, diagnostics
gone bad, brain state chain from the state machine's introspection, trigger firings), and a bag
with none of it still gives a PNG that lists every missing topic as absent."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from smart_brain.msg import MatchStatus, SmachContainerStatus, SmachContainerStructure
from std_msgs.msg import Int32, String

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
T0 = 1000.0


def status(path, active, t):
    m = SmachContainerStatus()
    m.header.stamp = rospy.Time(t)
    m.path, m.active_states = path, active
    return m


def write_match(path):
    """50 s at 10 Hz: truth on a line, estimate 0.03 m off in y for the first half and 0.01 m after
    (RMS sqrt((0.03^2 + 0.01^2) / 2), max 0.03); the machine goes GO -> TAKE (with inner GOTO) ->
    the opponent_ahead handler (a trigger firing) -> TAKE; score 12; two ERROR lines; one board
    diagnostic goes STALE."""
    with rosbag.Bag(path, 'w') as bag:
        for i in range(500):
            t = rospy.Time(T0 + i * 0.1)
            truth = Odometry()
            truth.header.stamp = t
            truth.header.frame_id = 'map'
            truth.pose.pose.position.x, truth.pose.pose.position.y = 0.3 + 0.004 * i, 1.0
            truth.pose.pose.orientation.w = 1.0
            bag.write('/sim/ground_truth', truth, t)
            est = PoseWithCovarianceStamped()
            est.header.stamp = t
            est.pose.pose.position.x = truth.pose.pose.position.x
            est.pose.pose.position.y = 1.0 + (0.03 if i < 250 else 0.01)
            est.pose.pose.orientation.w = 1.0
            bag.write('/mcl/pose', est, t)
        structure = SmachContainerStructure()
        structure.path = '/MATCH'
        structure.children = ['BODY', 'opponent_ahead']
        structure.internal_outcomes = ['fired', 'resume']
        structure.outcomes_from = ['BODY', 'opponent_ahead']
        structure.outcomes_to = ['opponent_ahead', 'BODY']
        bag.write('/brain/smach/container_structure', structure, rospy.Time(T0))
        for t, path, active in ((T0 + 0.0, '/MATCH', ['BODY']), (T0 + 0.0, '/MATCH/BODY', ['GO']),
                                (T0 + 10.0, '/MATCH/BODY', ['TAKE']), (T0 + 10.0, '/MATCH/BODY/TAKE', ['GOTO']),
                                (T0 + 20.0, '/MATCH', ['opponent_ahead']), (T0 + 25.0, '/MATCH', ['BODY'])):
            bag.write('/brain/smach/container_status', status(path, active, t), rospy.Time(t))
        match = MatchStatus()
        match.state, match.strategy, match.elapsed = 'ended', 'match', 49.9
        bag.write('/brain/match_status', match, rospy.Time(T0 + 49.9))
        bag.write('/sim/score', Int32(3), rospy.Time(T0 + 20))
        bag.write('/sim/score', Int32(12), rospy.Time(T0 + 40))
        for i, level in enumerate((Log.INFO, Log.ERROR, Log.FATAL, Log.WARN)):
            log = Log()
            log.level, log.name, log.msg = level, '/hal', 'line %d' % i
            bag.write('/rosout', log, rospy.Time(T0 + i))
        diag = DiagnosticArray()
        diag.status = [DiagnosticStatus(level=DiagnosticStatus.OK, name='hcl: motor_board'),
                       DiagnosticStatus(level=DiagnosticStatus.STALE, name='hcl: servo_board')]
        bag.write('/diagnostics', diag, rospy.Time(T0 + 5))


class ReportTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='product_report_')

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def report(self, bag):
        png = os.path.join(self.tmp, 'out.png')
        out = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'match_report.py'), bag, '-o', png],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=60)
        text = out.stdout.decode()
        self.assertEqual(out.returncode, 0, text)
        self.assertGreater(os.path.getsize(png), 10000)
        with open(os.path.join(self.tmp, 'out.txt')) as f:
            self.assertIn(f.read().strip(), text)
        return dict(l.split(': ', 1) for l in text.splitlines() if ': ' in l and not l.startswith('  '))

    def test_figures_of_a_known_match(self):
        bag = os.path.join(self.tmp, 'match.bag')
        write_match(bag)
        s = self.report(bag)
        rms = math.sqrt((0.03 ** 2 + 0.01 ** 2) / 2)
        self.assertEqual(s['localization error'], 'RMS %.3f m, max 0.030 m, heading max 0.0 deg' % rms)
        self.assertEqual(s['score'], '12 (/sim/score)')
        self.assertEqual(s['estimate'], '/mcl/pose (500 poses)')
        self.assertTrue(s['errors'].startswith('2 ERROR/FATAL log line(s), 1 diagnostic(s) went ERROR/STALE: hcl: servo_board'),
                        s['errors'])
        self.assertEqual(s['brain states'], '6 changes on /brain/smach/container_status')
        self.assertEqual(s['trigger firings'], '1 (opponent_ahead)')
        self.assertEqual(s['match'], 'ended, strategy match, 49.9 s elapsed')
        self.assertEqual(s['absent topics'], '/odom')

    def test_brain_state_chain(self):
        sys.path.insert(0, os.path.join(ROOT, 'scripts'))
        import match_report
        bag = os.path.join(self.tmp, 'match.bag')
        write_match(bag)
        topic, states = match_report.Match(bag).brain_states()
        self.assertEqual(topic, '/brain/smach/container_status')
        # The deepest active chain after each message (the handler interrupts, then BODY resumes).
        self.assertEqual([name for _, name in states],
                         ['MATCH/BODY', 'MATCH/BODY/GO', 'MATCH/BODY/TAKE', 'MATCH/BODY/TAKE/GOTO',
                          'MATCH/opponent_ahead', 'MATCH/BODY/TAKE/GOTO'])
        self.assertEqual([round(t - T0, 3) for t, _ in states], [0.0, 0.0, 10.0, 10.0, 20.0, 25.0])

    def test_any_bag_reports_what_is_absent(self):
        bag = os.path.join(self.tmp, 'other.bag')
        with rosbag.Bag(bag, 'w') as b:
            b.write('/something', String('x'), rospy.Time(5))
        s = self.report(bag)
        self.assertEqual(s['absent topics'], '/mcl/pose, /odom, /sim/ground_truth, /rosout, /diagnostics, '
                                             '/brain/... (states), /sim/...score...')
        self.assertEqual(s['score'], 'absent')
        self.assertTrue(s['localization error'].startswith('absent'))

    def test_unreadable_bag_is_one_line_not_a_crash(self):
        bag = os.path.join(self.tmp, 'broken.bag')
        with open(bag, 'wb') as f:
            f.write(b'#ROSBAG V2.0\n' + b'\0' * 100)
        out = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'match_report.py'), bag],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=60)
        self.assertEqual(out.returncode, 2)
        self.assertEqual(len(out.stderr.decode().strip().splitlines()), 1, out.stderr.decode())
        self.assertIn('cannot read', out.stderr.decode())


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_report', ReportTest, sys.argv)
