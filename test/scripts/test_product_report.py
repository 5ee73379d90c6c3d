#!/usr/bin/env python3
"""scripts/match_report.py on bags whose content is known: the figures in its summary are
the right ones (localization RMS/max error against the truth, score of both teams and score
events, match time from the start signal, driver goals and the aborted ones with their reason,
deduplicated warnings, ERROR lines, diagnostics gone bad after the start-up grace, brain state
chain from the state machine's introspection, trigger firings), a bag of the simulator before
the score attribution gives its plain score, and a bag with none of it still gives a PNG that
lists every missing topic as absent."""
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
from actionlib_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from genpy.dynamic import generate_dynamic
from geometry_msgs.msg import PoseWithCovarianceStamped
from hal_nodes.msg import GotoActionGoal, GotoActionResult, GotoResult
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from smart_brain.msg import MatchStatus, SmachContainerStatus, SmachContainerStructure
from std_msgs.msg import Int32, String
from visualization_msgs.msg import Marker, MarkerArray

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
T0 = 1000.0
START = T0 + 1.5  # the start signal: /brain/match_status running at T0 + 2 with 0.5 s elapsed

# The simulator's messages as a bag records them, built here from their definitions: the test
# needs neither robot_sim's generated classes nor a particular version of them (the report reads
# a bag of either, with getattr).
HEADER = '''================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
'''
MATCH_STATE_OLD = '''std_msgs/Header header
string year
bool started
bool over
float64 elapsed
float64 remaining
int32 score
'''
MATCH_STATE_NEW = MATCH_STATE_OLD + '''int32 score_ours
int32 score_opponent
''' + HEADER
MATCH_STATE_OLD += HEADER
SCORE_EVENTS = '''std_msgs/Header header
robot_sim/ScoreEvent[] events
''' + HEADER + '''================================================================================
MSG: robot_sim/ScoreEvent
float64 time
string element
string zone
int32 points
string team
'''
GAME_ELEMENTS = '''std_msgs/Header header
robot_sim/GameElementState[] elements
''' + HEADER + '''================================================================================
MSG: robot_sim/GameElementState
string kind
geometry_msgs/Pose2D pose
float64 radius
float64 height
bool carried
================================================================================
MSG: geometry_msgs/Pose2D
float64 x
float64 y
float64 theta
'''


def message_class(name, text):
    return generate_dynamic(name, text)[name]


def sim_match(definition, t, started, elapsed, score, ours=None, opponent=None):
    m = message_class('robot_sim/MatchState', definition)()
    m.header.stamp = rospy.Time(t)
    m.year, m.started, m.elapsed, m.remaining, m.score = '2009', started, elapsed, 90.0 - elapsed, score
    if ours is not None:
        m.score_ours, m.score_opponent = ours, opponent
    return m


def zone_marker(ns, ident, x0, y0, x1, y1):
    m = Marker()
    m.ns, m.id, m.type = ns, ident, Marker.CUBE
    m.pose.position.x, m.pose.position.y = (x0 + x1) / 2, (y0 + y1) / 2
    m.pose.orientation.w = 1.0
    m.scale.x, m.scale.y, m.scale.z = x1 - x0, y1 - y0, 0.001
    m.color.r, m.color.g, m.color.b, m.color.a = 0.2, 0.8, 0.2, 0.5
    return m


def goto(bag, ident, t_sent, t_end, x, y, angle, status, code, message):
    g = GotoActionGoal()
    g.header.stamp = rospy.Time(t_sent)
    g.goal_id.id, g.goal_id.stamp = ident, rospy.Time(t_sent)
    g.goal.x, g.goal.y, g.goal.angle = x, y, angle
    bag.write('/hal/driver/goto/goal', g, rospy.Time(t_sent))
    r = GotoActionResult()
    r.header.stamp = rospy.Time(t_end)
    r.status.goal_id = g.goal_id
    r.status.status, r.status.text = status, message
    r.result.code, r.result.message = code, message
    bag.write('/hal/driver/goto/result', r, rospy.Time(t_end))


def status(path, active, t):
    m = SmachContainerStatus()
    m.header.stamp = rospy.Time(t)
    m.path, m.active_states = path, active
    return m


def write_match(path):
    """50 s at 10 Hz: truth on a line, estimate 0.03 m off in y for the first half and 0.01 m after
    (RMS sqrt((0.03^2 + 0.01^2) / 2), max 0.03); the machine goes GO -> TAKE (with inner GOTO) ->
    the opponent_ahead handler (a trigger firing) -> TAKE; the start signal 1.5 s into the bag;
    score 12 to 5 (/sim/match score_ours/score_opponent, /sim/score_events); three goto goals
    (reached, blocked, preempted); two ERROR lines; a driver warning three times; a board
    diagnostic goes STALE after the start, another ERROR before it (start-up: not a fault); the
    table's zones, the elements and the opponent."""
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
        diag.header.stamp = rospy.Time(T0 + 1)
        diag.status = [DiagnosticStatus(level=DiagnosticStatus.ERROR, name='hcl: motor_board', message='booting')]
        bag.write('/diagnostics', diag, rospy.Time(T0 + 1))
        diag = DiagnosticArray()
        diag.header.stamp = rospy.Time(T0 + 5)
        diag.status = [DiagnosticStatus(level=DiagnosticStatus.OK, name='hcl: motor_board'),
                       DiagnosticStatus(level=DiagnosticStatus.STALE, name='hcl: servo_board')]
        bag.write('/diagnostics', diag, rospy.Time(T0 + 5))
        running = MatchStatus()
        running.header.stamp = rospy.Time(T0 + 2)
        running.state, running.strategy, running.elapsed = 'running', 'match', 0.5
        bag.write('/brain/match_status', running, rospy.Time(T0 + 2))
        for t, ours, opponent in ((T0 + 1, 0, 0), (T0 + 20, 3, 0), (T0 + 30, 3, 5), (T0 + 40, 12, 5)):
            bag.write('/sim/match', sim_match(MATCH_STATE_NEW, t, t >= START, max(0.0, t - START), ours, ours,
                                              opponent), rospy.Time(t))
        events = message_class('robot_sim/ScoreEvents', SCORE_EVENTS)()
        event = message_class('robot_sim/ScoreEvent', SCORE_EVENTS.split('MSG: robot_sim/ScoreEvent\n')[1])
        for when, element, zone, points, team in ((18.5, 'column#1', 'blue_zone', 3, 'ours'),
                                                  (28.5, 'ball_red#2', 'red_zone', 5, 'opponent'),
                                                  (38.5, 'column#3', 'blue_zone', 9, 'ours')):
            events.events.append(event(time=when, element=element, zone=zone, points=points, team=team))
            bag.write('/sim/score_events', events, rospy.Time(START + when))
        for i, text in enumerate(['route blocked by an obstacle'] * 3 + ['strategy match ended: aborted']):
            log = Log()
            log.header.stamp = rospy.Time(T0 + 30 + i)
            log.level = Log.WARN if i < 3 else Log.INFO
            log.name, log.msg = ('/hal', 'driver: goal ended: ' + text) if i < 3 else ('/brain', 'brain: ' + text)
            bag.write('/rosout', log, rospy.Time(T0 + 30 + i))
        goto(bag, 'g1', T0 + 3, T0 + 9, 0.8, 1.0, 0.0, GoalStatus.SUCCEEDED, GotoResult.REACHED, '')
        goto(bag, 'g2', T0 + 12, T0 + 19, 1.0, 0.5, math.pi / 2, GoalStatus.ABORTED, GotoResult.BLOCKED,
             'route blocked by an obstacle')
        goto(bag, 'g3', T0 + 26, T0 + 27, 2.0, 1.5, math.pi, GoalStatus.PREEMPTED, GotoResult.CANCELED, 'new goal')
        markers = MarkerArray()
        table = zone_marker('table', 0, 0.0, 0.0, 3.0, 2.0)
        markers.markers = [table, zone_marker('start_zones', 0, 0.0, 0.0, 0.5, 0.5),
                           zone_marker('start_zones', 1, 2.5, 0.0, 3.0, 0.5),
                           zone_marker('score_zones', 2, 1.2, 1.6, 1.8, 2.0)]
        bag.write('/table_markers', markers, rospy.Time(T0))
        elements = message_class('robot_sim/GameElements', GAME_ELEMENTS)
        state = message_class('robot_sim/GameElementState', GAME_ELEMENTS.split('MSG: robot_sim/GameElementState\n')[1])
        for t, x in ((T0, 1.0), (T0 + 49, 1.5)):
            msg = elements()
            msg.header.stamp = rospy.Time(t)
            for kind, y in (('column', 1.8), ('ball_red', 0.5)):
                e = state(kind=kind, radius=0.04)
                e.pose.x, e.pose.y = x, y
                msg.elements.append(e)
            bag.write('/sim/elements', msg, rospy.Time(t))
        for i in range(50):
            opp = Odometry()
            opp.header.stamp = rospy.Time(T0 + i)
            opp.pose.pose.position.x, opp.pose.pose.position.y = 2.7 - 0.02 * i, 0.3 + 0.02 * i
            opp.pose.pose.orientation.w = 1.0
            bag.write('/sim/opponent', opp, rospy.Time(T0 + i))


def write_old_match(path):
    """A bag of the simulator before the score attribution: /sim/match with only `score` (its
    `started` is the start signal), /sim/score; no brain, no score events."""
    with rosbag.Bag(path, 'w') as bag:
        for t, started, score in ((T0, False, 0), (T0 + 4, True, 0), (T0 + 10, True, 7)):
            bag.write('/sim/match', sim_match(MATCH_STATE_OLD, t, started, 1.0 if started else 0.0, score),
                      rospy.Time(t))
            bag.write('/sim/score', Int32(score), rospy.Time(t))


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
        self.text = text
        return dict(l.split(': ', 1) for l in text.splitlines() if ': ' in l and not l.startswith('  '))

    def test_figures_of_a_known_match(self):
        bag = os.path.join(self.tmp, 'match.bag')
        write_match(bag)
        s = self.report(bag)
        rms = math.sqrt((0.03 ** 2 + 0.01 ** 2) / 2)
        self.assertEqual(s['localization error'], 'RMS %.3f m, max 0.030 m, heading max 0.0 deg' % rms)
        self.assertEqual(s['score'], 'ours 12, opponent 5')
        self.assertEqual(s['score source'], '/sim/match, 3 score event(s) on /sim/score_events')
        self.assertEqual(s['start signal'], '/brain/match_status (running), 1.5 s after the bag start')
        self.assertEqual(s['estimate'], '/mcl/pose (500 poses)')
        # The motor board's ERROR before the start signal is start-up, not a fault.
        self.assertEqual(s['errors'], '2 ERROR/FATAL log line(s), 1 diagnostic(s) went ERROR/STALE: hcl: servo_board')
        self.assertEqual(s['brain states'], '6 changes on /brain/smach/container_status')
        self.assertEqual(s['trigger firings'], '1 (opponent_ahead)')
        self.assertEqual(s['match'], 'ended, strategy match, 49.9 s elapsed')
        self.assertEqual(s['strategy outcomes'], 'strategy match ended: aborted (at 31.5 s)')
        self.assertEqual(s['driver goals'], 'goto 3 (1 succeeded, 1 aborted, 1 preempted)')
        self.assertEqual(s['aborted goals'], '1')
        self.assertEqual(s['warnings'], '3 WARN line(s) of the brain and the driver, 1 distinct')
        self.assertEqual(s['opponent'], '/sim/opponent (50 poses)')
        self.assertEqual(s['table'], '3.00 x 2.00 m (/table_markers), 2 start zone(s), 1 score zone(s), 2 element(s)')
        self.assertEqual(s['absent topics'], '/odom')
        text = self.text
        # Times are match times: 0 at the start signal, T0 + 1.5.
        self.assertIn('  10.5 s goto #2 to (1.00, 0.50, 90 deg): ABORTED/BLOCKED: route blocked by an obstacle', text)
        self.assertIn('  3x /hal: driver: goal ended: route blocked by an obstacle (first at 28.5 s)', text)
        self.assertIn('  diagnostic hcl: servo_board: STALE at 3.5 s', text)
        self.assertIn('    18.5 s ours     +3 column#1 in blue_zone', text)
        self.assertIn('    18.5 s opponent_ahead', text)
        self.assertNotIn('motor_board', text)

    def test_score_of_a_bag_without_attribution(self):
        bag = os.path.join(self.tmp, 'old.bag')
        write_old_match(bag)
        s = self.report(bag)
        self.assertEqual(s['score'], '7 (no attribution in this bag)')
        self.assertEqual(s['score source'], '/sim/match')
        self.assertEqual(s['start signal'], '/sim/match (started), 3.0 s after the bag start')
        self.assertEqual(s['driver goals'], 'absent')

    def test_driver_goals_and_match_time(self):
        from robot_tools.report import match_bag
        bag = os.path.join(self.tmp, 'match.bag')
        write_match(bag)
        m = match_bag.Match(bag)
        self.assertEqual(m.start_signal(), (START, '/brain/match_status (running)'))
        goals = m.driver_goals()
        self.assertEqual([(g['action'], g['n'], g['status'], g['code']) for g in goals],
                         [('goto', 1, 'SUCCEEDED', 'REACHED'), ('goto', 2, 'ABORTED', 'BLOCKED'),
                          ('goto', 3, 'PREEMPTED', 'CANCELED')])
        self.assertEqual([(e[1], e[2]) for e in m.score_events()], [('ours', 3), ('opponent', 5), ('ours', 9)])
        start, end = m.elements()
        self.assertEqual([(k, x, y) for k, x, y, _, _ in start], [('column', 1.0, 1.8), ('ball_red', 1.0, 0.5)])
        self.assertEqual([(k, x, y) for k, x, y, _, _ in end], [('column', 1.5, 1.8), ('ball_red', 1.5, 0.5)])

    def test_brain_state_chain(self):
        from robot_tools.report import match_bag
        bag = os.path.join(self.tmp, 'match.bag')
        write_match(bag)
        topic, states = match_bag.Match(bag).brain_states()
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
                                             '/brain/... (states), /sim/...score..., /sim/elements, /sim/opponent, '
                                             '/hal/driver/goto/goal, /sim/score_events, /table_markers, /sim/markers')
        self.assertEqual(s['start signal'], 'absent (times below count from the bag start)')
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
