#!/usr/bin/env python3
"""A passing fault must not end the match: whole simulated matches of the `match` strategy
(test/launch/match_faults_*.test), judged in simulated time.

Parameters (~private): ~actions, the HAL action servers whose goals count as busy (idle
measure); ~faults, a list of {at: match time [s], kind, target, duration, magnitude}
given to /sim/inject_fault at that match time, or kind `kidnap` (our robot moved `magnitude`
metres toward the table's centre with /sim/teleport); ~park_opponent: [x, y, theta] where the
opponent is held for the whole match (empty: it plays as configured).

Checked:
- after each fault ends, the robot commands a non-zero speed again within ~resume_within
  (5 s) of simulated time, and again in the 2 * resume_within after that (it plays on);
- ~score_after (a match time, or absent): our score grows after it;
- ~replan_within (with ~park_opponent): a goal the driver ended BLOCKED is followed by a goal
  to another place within that many seconds;
- no idle stretch (robot_tools.matches.idle_time) over 10 s while more than 10 s of the match remain.
"""
import math
import os
import threading
import time
import unittest

import rospy
import rostest
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from geometry_msgs.msg import Pose2D, Twist
from hal_nodes.msg import GotoActionGoal, GotoActionResult, GotoResult
from robot_sim.msg import MatchState
from robot_sim.srv import InjectFault, PlaceOpponent
from smart_brain.msg import MatchStatus
from std_srvs.srv import Trigger

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.chaos.injector import kidnap
from robot_tools.matches.idle_time import idle_stretches, too_long


def note(fmt, *args):
    """A figure for the log (rostest keeps the test's output)."""
    print('test_match_faults: ' + fmt % args, flush=True)


class Live(object):
    """What the test follows during the match, stamped in simulated time."""

    def __init__(self):
        self.lock = threading.Lock()
        self.commands = []      # (t, v, w) on /hal/drive/cmd_vel
        self.spans = {}         # action -> [[t_active, t_done]] from its status (one goal at a time)
        self.goto_goals = []    # (t, x, y)
        self.blocked = []       # t of goto results BLOCKED
        self.scores = []        # (t, score_ours)
        self.match = None
        self.status = None
        rospy.Subscriber('/hal/drive/cmd_vel', Twist, self._cmd, queue_size=200, tcp_nodelay=True)
        rospy.Subscriber('/hal/driver/goto/goal', GotoActionGoal, self._goto, queue_size=50)
        rospy.Subscriber('/hal/driver/goto/result', GotoActionResult, self._goto_result, queue_size=50)
        for topic in rospy.get_param('~actions'):
            rospy.Subscriber(topic + '/status', GoalStatusArray, self._action_status(topic), queue_size=50)
        rospy.Subscriber('/sim/match', MatchState, self._match, queue_size=10)
        rospy.Subscriber('/brain/match_status', MatchStatus, self._status, queue_size=10)

    def _cmd(self, m):
        with self.lock:
            self.commands.append((rospy.get_time(), m.linear.x, m.angular.z))

    def _goto(self, m):
        with self.lock:
            self.goto_goals.append((rospy.get_time(), m.goal.x, m.goal.y))

    def _goto_result(self, m):
        with self.lock:
            if m.result.code == GotoResult.BLOCKED:
                self.blocked.append(rospy.get_time())

    def _action_status(self, topic):
        def on_status(m):
            active = any(st.status in (GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.PREEMPTING)
                         for st in m.status_list)
            with self.lock:
                spans = self.spans.setdefault(topic, [])
                if active and (not spans or spans[-1][1] is not None):
                    spans.append([rospy.get_time(), None])
                elif not active and spans and spans[-1][1] is None:
                    spans[-1][1] = rospy.get_time()
        return on_status

    def _match(self, m):
        with self.lock:
            self.match = m
            if not self.scores or self.scores[-1][1] != m.score_ours:
                self.scores.append((rospy.get_time(), m.score_ours))

    def _status(self, m):
        self.status = m


class MatchFaultsTest(unittest.TestCase):
    def test_the_match_goes_on_through_the_faults(self):
        rospy.init_node('test_match_faults')
        live = Live()
        faults = rospy.get_param('~faults', [])
        park = rospy.get_param('~park_opponent', [])
        resume_within = float(rospy.get_param('~resume_within', 5.0))
        duration = float(rospy.get_param('/brain/match/duration'))
        deadline = time.monotonic() + 120.0
        while time.monotonic() < deadline and not (live.status and live.status.ready):
            time.sleep(0.2)
        self.assertTrue(live.status and live.status.ready, 'the robot never became ready: %s' % (live.status,))
        if park:
            place = rospy.ServiceProxy('/sim/place_opponent', PlaceOpponent)
            self.assertTrue(place(pose=Pose2D(*park), hold=True).ok)
        inject = rospy.ServiceProxy('/sim/inject_fault', InjectFault)
        rospy.wait_for_service('/brain/start', 10.0)
        self.assertTrue(rospy.ServiceProxy('/brain/start', Trigger)().success)
        t0 = rospy.get_time()   # the match starts now (simulated time)
        for f in faults:
            if f['kind'] != 'kidnap':
                r = inject(kind=f['kind'], target=str(f.get('target', '')), start=t0 + f['at'],
                           duration=f['duration'], magnitude=f.get('magnitude', 0.0), clear=False)
                self.assertTrue(r.ok, r.message)
        kidnaps = [f for f in faults if f['kind'] == 'kidnap']
        while rospy.get_time() < t0 + duration + 1.0 and time.monotonic() < deadline + 300.0:
            if kidnaps and rospy.get_time() >= t0 + kidnaps[0]['at']:
                self.kidnap(kidnaps.pop(0)['magnitude'])
            time.sleep(0.01)
        self.assertTrue(live.match is not None and live.match.over, 'the match never ended: %s' % (live.match,))
        end = t0 + duration
        with live.lock:
            commands = list(live.commands)
            spans = [tuple(s) for spans in live.spans.values() for s in spans]
            goto_goals, blocked, scores = list(live.goto_goals), list(live.blocked), list(live.scores)
        summary = 'score %s, %d commands, %d goals, blocked at %s' % (
            scores[-1:], len(commands), len(spans), ['%.1f' % (t - t0) for t in blocked])
        note('%s', summary)

        for f in faults:
            fault_end = t0 + f['at'] + f.get('duration', 0.0)
            moving = [t for t, v, w in commands
                      if fault_end <= t <= fault_end + resume_within and (abs(v) > 1e-3 or abs(w) > 1e-3)]
            self.assertTrue(moving, '%s: no speed commanded within %.1f s of its end (%.1f s into the match); %s'
                            % (f['kind'], resume_within, fault_end - t0, summary))
            note('%s at %.1f s: driving again %.2f s after it ended',
                          f['kind'], f['at'], moving[0] - fault_end)
            # ... and it keeps playing: a fault seen late (a kidnap, noticed by the localization
            # after the robot drove on) must not stop it either.
            later = [t for t, v, w in commands
                     if fault_end + resume_within < t <= min(end, fault_end + 3 * resume_within) and (abs(v) > 1e-3 or abs(w) > 1e-3)]
            self.assertTrue(later, '%s: no speed commanded from %.1f to %.1f s after it ended; %s'
                            % (f['kind'], resume_within, 3 * resume_within, summary))
        score_after = rospy.get_param('~score_after', None)
        if score_after is not None:
            before = [s for t, s in scores if t <= t0 + score_after]
            self.assertGreater(scores[-1][1], before[-1] if before else 0,
                               'no point scored after %.0f s: %s' % (score_after, scores))
        replan_within = rospy.get_param('~replan_within', None)
        if replan_within is not None:
            self.assertTrue(blocked, 'the parked opponent never blocked a goal: %s' % summary)
            first = blocked[0]
            stuck_at = [(x, y) for t, x, y in goto_goals if t <= first][-1]
            other = [t for t, x, y in goto_goals
                     if first < t <= first + replan_within and math.hypot(x - stuck_at[0], y - stuck_at[1]) > 0.2]
            self.assertTrue(other, 'no goal elsewhere within %.0f s of the first BLOCKED (%.1f s into the match): %s'
                            % (replan_within, first - t0, [('%.1f' % (t - t0), x, y) for t, x, y in goto_goals]))
        idle = idle_stretches(sorted(spans), commands, t0, end)
        note('idle %.1f s, longest %.1f s', sum(b - a for a, b in idle),
                      max([b - a for a, b in idle] or [0.0]))
        self.assertEqual(too_long(idle, end), [], 'idle too long while the match ran: %s' % idle)

    def kidnap(self, distance):
        said = kidnap(distance)
        self.assertTrue(said.startswith('kidnapped'), said)
        note('%s', said)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_match_faults', MatchFaultsTest)
