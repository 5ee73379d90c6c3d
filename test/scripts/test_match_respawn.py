#!/usr/bin/env python3
"""Product nodes killed mid-match come back where they were (test/launch/match_respawn_*.test):
one simulated match of the `match` strategy, as fast as the machine goes, with `kill -9` of
hcl_node, hal_node and the brain at the ~kills match times (robot_tools.chaos.injector), and the
brain killed again just before the end so that it is dead when the match ends. roslaunch
respawns each one (launch/<robot>.launch: respawn, respawn_delay).

Checked, one case per node:
- hcl_node: the robot drives again within ~drive_within wall seconds after the node answers
  again (a restart is processes starting, in wall time; at the factor this match runs at, the
  same wait is two to three times as long in simulated time);
- hal_node: localization resumes from its saved pose (~save_pose_rate): its first pose after
  the restart is within ~resume_tolerance of the truth (not a guess across the table), it is
  within ~recovered_m within ~recovered_within of that first pose; the robot drives again;
- brain: it resumes the match (running, elapsed time kept within ~elapsed_tolerance, never
  waiting for the start cord again); the robot drives again;
- the match scores after the first kill;
- the brain dead at the end: hal_node's match-end backstop turns the effectors off within 1 s of
  the match end, and the match state still says ended once the brain is back.
"""
import math
import os
import tempfile
import threading
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from geometry_msgs.msg import PoseWithCovarianceStamped
from robot_sim.msg import MatchState
from smart_brain.msg import MatchStatus
from std_msgs.msg import Bool
from std_srvs.srv import Trigger

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.chaos.injector import FaultInjector

MOVED = 0.05  # [m] of true displacement that counts as driving


class Record(object):
    """What the test follows, stamped in simulated time (the truth also in wall time)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.truth, self.poses, self.statuses, self.effectors, self.scores = [], [], [], [], []
        self.truth_wall = []
        rospy.Subscriber('/sim/ground_truth', Odometry, self._truth, queue_size=50)
        rospy.Subscriber('/mcl/pose', PoseWithCovarianceStamped, self._pose, queue_size=50)
        rospy.Subscriber('/brain/match_status', MatchStatus, self._status, queue_size=20)
        rospy.Subscriber('/effectors/deactivated', Bool, self._effectors, queue_size=10)
        rospy.Subscriber('/sim/match', MatchState, self._match, queue_size=10)
        self.status = None

    def _truth(self, m):
        with self.lock:
            self.truth.append((rospy.get_time(), m.pose.pose.position.x, m.pose.pose.position.y))
            self.truth_wall.append(time.monotonic())

    def _pose(self, m):
        with self.lock:
            self.poses.append((rospy.get_time(), m.pose.pose.position.x, m.pose.pose.position.y))

    def _status(self, m):
        self.status = m
        with self.lock:
            self.statuses.append((rospy.get_time(), m.state, m.elapsed))

    def _effectors(self, m):
        with self.lock:
            self.effectors.append((rospy.get_time(), m.data))

    def _match(self, m):
        with self.lock:
            if not self.scores or self.scores[-1][1] != m.score_ours:
                self.scores.append((rospy.get_time(), m.score_ours))


def truth_at(truth, t):
    """The first true position at or after t."""
    return next(((x, y) for s, x, y in truth if s >= t), None)


class MatchRespawnTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_match_respawn')
        cls.rec = Record()
        cls.duration = float(rospy.get_param('/brain/match/duration'))
        deadline = time.monotonic() + 120.0
        while time.monotonic() < deadline and not (cls.rec.status and cls.rec.status.ready):
            time.sleep(0.2)
        assert cls.rec.status and cls.rec.status.ready, 'the robot never became ready: %s' % (cls.rec.status,)
        rospy.wait_for_service('/brain/start', 10.0)
        assert rospy.ServiceProxy('/brain/start', Trigger)().success
        cls.t0 = rospy.get_time()
        kills = [dict(at=float(k['at']), kind='kill', target=k['node']) for k in rospy.get_param('~kills')]
        kills.append(dict(at=cls.duration - float(rospy.get_param('~brain_dead_before_end')), kind='kill',
                          target='/brain'))
        cls.injector = FaultInjector(kills, os.path.join(tempfile.mkdtemp(prefix='match_respawn_'), 'faults.yaml'),
                                     cls.t0)
        cls.injector.start()
        while rospy.get_time() < cls.t0 + cls.duration + 3.0 and time.monotonic() < deadline + 400.0:
            time.sleep(0.05)
        cls.injector.wait(60.0)
        ended_by = time.monotonic() + 20.0  # the brain killed before the end says `ended` once back
        while time.monotonic() < ended_by and not (cls.rec.status and cls.rec.status.state == 'ended'):
            time.sleep(0.1)
        with cls.rec.lock:
            cls.truth, cls.poses, cls.truth_wall = list(cls.rec.truth), list(cls.rec.poses), list(cls.rec.truth_wall)
            cls.statuses, cls.effectors = list(cls.rec.statuses), list(cls.rec.effectors)
            cls.scores = list(cls.rec.scores)
        for d in cls.injector.done:
            print('test_match_respawn: %s %s at %.1f s, back at %.1f s: %s'
                  % (d['kind'], d['target'], d['start'] - cls.t0, d['end'] - cls.t0, d['outcome']), flush=True)
        print('test_match_respawn: scores %s' % [('%.1f' % (t - cls.t0), s) for t, s in cls.scores], flush=True)

    def kill_of(self, node, first=True):
        done = sorted((d for d in self.injector.done if d['target'] == node), key=lambda d: d['start'])
        self.assertTrue(done, 'no kill of %s was done' % node)
        d = done[0] if first else done[-1]
        self.assertIn('back as pid', d['outcome'], d)
        return d

    def assertDrivesAgain(self, d):
        within = float(rospy.get_param('~drive_within'))  # [s, wall]
        back = next(i for i, (t, _, _) in enumerate(self.truth) if t >= d['end'])
        a = self.truth[back]
        drove = next((i for i in range(back, len(self.truth))
                      if math.hypot(self.truth[i][1] - a[1], self.truth[i][2] - a[2]) > MOVED), None)
        wall = self.truth_wall[drove] - self.truth_wall[back] if drove is not None else None
        said = '%s back at %.1f s, the robot drove %s' % (
            d['target'], d['end'] - self.t0, 'never again' if drove is None else '%.1f s later (%.1f s wall)'
            % (self.truth[drove][0] - d['end'], wall))
        print('test_match_respawn: %s' % said, flush=True)
        states = []  # what the brain said meanwhile: why it did not drive, when it did not
        for t, state, _ in self.statuses:
            if t >= d['end'] and (not states or states[-1][1] != state):
                states.append(('%.1f' % (t - self.t0), state))
        self.assertTrue(wall is not None and wall <= within, '%s: not within %.0f s (wall) of its return; the brain '
                        'meanwhile: %s; /mcl/pose after it: %d' % (said, within, states[:8],
                                                                   sum(1 for t, _, _ in self.poses if t >= d['end'])))

    def test_hcl_killed_the_robot_drives_on(self):
        self.assertDrivesAgain(self.kill_of('/hcl'))

    def test_hal_killed_localization_resumes_from_the_saved_pose(self):
        d = self.kill_of('/hal')
        first = next(((t, x, y) for t, x, y in self.poses if t > d['start'] + 0.05), None)
        self.assertIsNotNone(first, 'no /mcl/pose after the HAL came back')
        tx, ty = truth_at(self.truth, first[0])
        error = math.hypot(first[1] - tx, first[2] - ty)
        print('test_match_respawn: first pose after the HAL restart (%.1f s): %.3f m from the truth'
              % (first[0] - self.t0, error), flush=True)
        self.assertLess(error, float(rospy.get_param('~resume_tolerance')))
        near, within = float(rospy.get_param('~recovered_m')), float(rospy.get_param('~recovered_within'))
        back = [t for t, x, y in self.poses if first[0] <= t <= first[0] + within
                and math.hypot(x - truth_at(self.truth, t)[0], y - truth_at(self.truth, t)[1]) < near]
        self.assertTrue(back, 'localization not within %.2f m of the truth within %.0f s of its first pose'
                        % (near, within))
        self.assertDrivesAgain(d)

    def test_brain_killed_resumes_the_match(self):
        d = self.kill_of('/brain')
        after = [(t, state, elapsed) for t, state, elapsed in self.statuses if t > d['start'] + 0.05]
        self.assertTrue(after, 'no /brain/match_status after the brain came back')
        self.assertNotIn('waiting_for_start', {s for t, s, e in self.statuses if t > self.t0 + 0.5})
        t, state, elapsed = after[0]
        self.assertEqual(state, 'running')
        self.assertAlmostEqual(elapsed, t - self.t0, delta=float(rospy.get_param('~elapsed_tolerance')))
        self.assertDrivesAgain(d)

    def test_the_match_scores_after_the_first_kill(self):
        first = min(d['start'] for d in self.injector.done)
        before = [s for t, s in self.scores if t <= first]
        self.assertTrue(self.scores, 'no score from the referee')
        self.assertGreater(self.scores[-1][1], before[-1] if before else 0, 'no point scored after the first kill: %s'
                           % self.scores)

    def test_brain_dead_at_the_end_hal_ends_the_match(self):
        d = self.kill_of('/brain', first=False)
        end = self.t0 + self.duration
        self.assertGreater(d['end'], end, 'the brain was back before the end: the backstop was not needed')
        off = [t for t, data in self.effectors if data and t <= end + 1.0]
        self.assertTrue(off, 'the effectors were not off 1 s after the match end: %s' % self.effectors)
        self.assertGreaterEqual(off[0], end - 0.5, 'deactivated before the end: %s' % self.effectors)
        self.assertEqual(self.statuses[-1][1], 'ended', self.statuses[-3:])


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_match_respawn', MatchRespawnTest)
