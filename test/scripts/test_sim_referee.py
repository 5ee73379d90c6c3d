#!/usr/bin/env python3
"""The referee and readiness on the simulated 2009 robot (test/launch/sim_referee_eurobot2009.test).

- Ready means ready: the brain's status says ready only while every board and device item on
  /diagnostics_agg is OK, and /diagnostics_agg has one item per board and per device the HCL and
  the HAL loaded (their ~status_names), none missing.
- One start: /brain/start (no cord) starts the simulated referee's match as well.
- The idle strategy scores nothing of its own: at the match end our score is 0; whatever the
  opponent pushed into a zone is the opponent's (the score events say whose).
- A second simulation started on this one's channels (beacon pty, camera port)
  refuses at once, naming them, and this one's boards keep working.
"""
import os
import subprocess
import time
import sys
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from robot_sim.msg import MatchState, ScoreEvents
from smart_brain.msg import MatchStatus
from std_srvs.srv import Trigger

from test_support import DeviceDiagnostics, Recorder, is_ok, wait_for


def leaves(agg):
    return {s.name: s for s in agg.status if s.name.startswith(('/Boards/', '/Devices/')) and s.name.count('/') == 2}


class SimRefereeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_sim_referee')

    def test_ready_one_start_and_our_score(self):
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
        # ... every board and device the hosts loaded, by the names they say they publish.
        loaded = rospy.get_param('/hcl/status_names') + rospy.get_param('/hal/status_names')
        self.assertIn('hal/odometry: device', loaded)
        self.assertEqual(len(loaded), len(items), (loaded, sorted(items)))
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

    def test_second_simulation_on_the_same_channels_refuses(self):
        beacons_pty = rospy.get_param('/sim/firmware/beacons/port')
        self.assertTrue(os.path.exists(beacons_pty))
        # The same world and emulators (the same channels) in another namespace.
        rospy.set_param('/second/sim', rospy.get_param('/sim'))
        rospy.set_param('/second/table', rospy.get_param('/table'))
        rospy.set_param('/second/brain/match/duration', rospy.get_param('/brain/match/duration'))
        out = subprocess.run(['rosrun', 'robot_sim', 'simulator', '__ns:=/second', '__name:=sim'],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=30)
        text = out.stdout.decode(errors='replace')
        self.assertNotEqual(out.returncode, 0, text)
        self.assertIn('refusing to start', text)
        for channel in ('TCP port %d' % rospy.get_param('/sim/firmware/camera/port'), beacons_pty):
            self.assertIn(channel, text)
        # The running simulation lost nothing: its pty is there and its boards still answer.
        self.assertTrue(os.path.exists(beacons_pty), 'the second simulation removed the first one\'s beacon pty')
        diag = DeviceDiagnostics()
        since = time.monotonic() + 0.5
        for name in ('hcl/beacons', 'hcl/motor_board', 'hal/beacons'):
            status = diag.wait_for(name, lambda s: True, 5.0, since=since)
            self.assertIsNotNone(status, name)
            self.assertTrue(is_ok(status), '%s: %s' % (name, status.message))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'sim_referee_eurobot2009', SimRefereeTest, sys.argv)
