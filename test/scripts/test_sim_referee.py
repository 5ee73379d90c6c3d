#!/usr/bin/env python3
"""The referee and readiness on the simulated 2009 robot (test/launch/sim_referee_eurobot2009.test).

- Ready means ready: the brain's status says ready only while every board and device item on
  /diagnostics_agg is OK, and /diagnostics_agg has one item per board and per device.
- One start: /brain/start (no cord) starts the simulated referee's match as well.
- The idle strategy scores nothing of its own: at the match end our score is 0; whatever the
  opponent pushed into a zone is the opponent's (the score events say whose).
"""
import sys
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from robot_sim.msg import MatchState, ScoreEvents
from smart_brain.msg import MatchStatus
from std_srvs.srv import Trigger

from hal_test_common import Recorder, wait_for


def leaves(agg):
    return {s.name: s for s in agg.status if s.name.startswith(('/Boards/', '/Devices/')) and s.name.count('/') == 2}


class SimRefereeTest(unittest.TestCase):
    def test_ready_one_start_and_our_score(self):
        rospy.init_node('test_sim_referee')
        brain = Recorder('/brain/match_status', MatchStatus)
        referee = Recorder('/sim/match', MatchState)
        agg = Recorder('/diagnostics_agg', DiagnosticArray, queue_size=50)
        events = Recorder('/sim/score_events', ScoreEvents)
        self.assertTrue(wait_for(lambda: brain.last() is not None and brain.last().ready, 90.0, 0.2),
                        'the brain never said ready: %s' % (brain.last(),))
        status = brain.last()
        self.assertEqual(status.state, 'waiting_for_start')
        self.assertEqual(status.readiness, 'ready')
        # Ready was said while every board and device was OK on /diagnostics_agg.
        self.assertTrue(wait_for(lambda: agg.last() is not None, 10.0))
        items = leaves(agg.last())
        for name in ('/Boards/motor_board: board', '/Boards/servo_board: board', '/Devices/odometry: device',
                     '/Devices/localization: device', '/Devices/driver: device'):
            self.assertIn(name, items, sorted(items))
        bad = {n: s.message for n, s in items.items() if s.level != DiagnosticStatus.OK}
        self.assertEqual(bad, {}, 'ready while not every item is OK')
        # Not started yet: the referee waits for the cord.
        self.assertFalse(referee.last().started)
        rospy.wait_for_service('/brain/start', 10.0)
        self.assertTrue(rospy.ServiceProxy('/brain/start', Trigger)().success)
        self.assertTrue(wait_for(lambda: referee.last().started, 3.0),
                        '/brain/start did not start the simulated match: %s' % referee.last())
        self.assertEqual(referee.last().colour_ours, 'red')
        self.assertEqual(referee.last().colour_opponent, 'green')
        # The match ends on both sides after the brain's duration, in simulated time.
        self.assertTrue(wait_for(lambda: referee.last().over, 40.0, 0.1), 'the referee never ended the match')
        self.assertTrue(wait_for(lambda: brain.last().state == 'ended', 5.0, 0.1), brain.last())
        self.assertAlmostEqual(referee.last().elapsed, 10.0, delta=0.2)
        final = referee.last()
        self.assertEqual(final.score_ours, 0, 'idle scores nothing of its own: %s' % final)
        self.assertEqual(final.score, final.score_ours)
        scored = events.last().events if events.last() is not None else []
        self.assertFalse([e for e in scored if e.team == 'ours'], scored)
        self.assertEqual(sum(e.points for e in scored if e.team == 'opponent'), final.score_opponent)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'sim_referee_eurobot2009', SimRefereeTest, sys.argv)
