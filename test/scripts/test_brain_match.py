#!/usr/bin/env python3
"""The brain under the match timer (test/launch/brain_match.test).

The test serves /test/long_action (actionlib's TestAction: goal 1 succeeds after 0.3 s,
goals 2 and 3 run until cancelled, like long drives) and plays the start cord and an
obstacle flag; HAL (hal_node with the skeleton's effector) is real.
"""
import subprocess
import sys
import threading
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib.msg import TestAction, TestResult
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from hal_nodes.msg import HumanInput
from smart_brain.msg import ActionStatus, MatchStatus, SmachContainerStatus, SmachContainerStructure
from smart_brain.srv import StartAction, SwitchStrategy
from std_msgs.msg import Bool
from test_support import Recorder, wait_for

DURATION = 9.0   # brain_match.test: match/duration


class Server(object):
    """Records every goal: (value, accepted at, cancelled at, ended status)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.goals = []
        self.server = actionlib.ActionServer('/test/long_action', TestAction, self._on_goal, self._on_cancel,
                                             auto_start=False)
        self.server.start()

    def _on_goal(self, gh):
        gh.set_accepted()
        rec = {'value': gh.get_goal().goal, 'accepted': time.monotonic(), 'cancelled': None, 'gh': gh, 'end': None}
        with self.lock:
            self.goals.append(rec)
        if rec['value'] == 1:
            def finish():
                time.sleep(0.3)
                with self.lock:
                    if rec['end'] is None:
                        rec['end'] = GoalStatus.SUCCEEDED
                        gh.set_succeeded(TestResult(result=1))
            threading.Thread(target=finish, daemon=True).start()

    def _on_cancel(self, gh):
        with self.lock:
            for rec in self.goals:
                if rec['gh'] == gh and rec['end'] is None:
                    rec['cancelled'] = time.monotonic()
                    rec['end'] = GoalStatus.PREEMPTED
                    gh.set_canceled()

    def snapshot(self):
        with self.lock:
            return [dict(r) for r in self.goals]


class BrainMatchTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_brain_match')
        cls.server = Server()
        cls.match = Recorder('/brain/match_status', MatchStatus)
        cls.actions = Recorder('/brain/action_status', ActionStatus)
        cls.status = Recorder('/brain/smach/container_status', SmachContainerStatus)
        cls.structure = Recorder('/brain/smach/container_structure', SmachContainerStructure)
        cls.cmd_vel = Recorder('/hal/drive/cmd_vel', Twist)
        cls.deactivated = Recorder('/effectors/deactivated', Bool)
        cls.hmi = rospy.Publisher('/hal/hmi/input', HumanInput, queue_size=1, latch=True)
        cls.obstacle = rospy.Publisher('/test/obstacle', Bool, queue_size=1)
        ok = wait_for(lambda: cls.match.last() is not None and cls.match.last().state == 'waiting_for_start', 60.0, 0.1)
        assert ok, 'the brain never reported waiting_for_start: %s' % cls.match.last()
        assert wait_for(lambda: cls.deactivated.last() is not None, 30.0, 0.1), 'hal_node not up'

    def test_0_a_missing_device_or_strategy_stops_the_brain_with_one_clear_line(self):
        for args, expect in ((['_strategy:=homologation', '_device_timeout:=1'], '/hal/driver'),
                             (['_strategy:=no_such_strategy'], 'allowed values:')):
            out = subprocess.run(['rosrun', 'smart_brain', 'brain', '__name:=brain_bad'] + args,
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=30)
            text = out.stdout.decode()
            self.assertEqual(out.returncode, 2, text)
            fatal = [line for line in text.splitlines() if 'FATAL' in line]
            self.assertEqual(len(fatal), 1, text)
            self.assertIn(expect, fatal[0])

    def test_match(self):
        # 1. Nothing moves before the start signal.
        time.sleep(1.0)
        self.assertEqual(self.server.snapshot(), [], 'a goal was sent before the start signal')
        self.assertFalse(self.deactivated.last().data)

        # Strategies switch at runtime (here before the start): unknown names are refused.
        switch = rospy.ServiceProxy('/brain/switch_strategy', SwitchStrategy)
        res = switch('no_such_strategy')
        self.assertFalse(res.success)
        self.assertIn('brain_test_drive', res.available)
        for name in ('brain_bench_idle', 'brain_test_drive'):
            res = switch(name)
            self.assertTrue(res.success, res.message)
            self.assertTrue(wait_for(lambda: self.match.last().strategy == name, 5.0), self.match.last())
        self.assertEqual(self.match.last().state, 'waiting_for_start')

        # 2. The cord is pulled: the strategy runs; leg 1 succeeds, leg 2 starts.
        self.hmi.publish(HumanInput(cord_inserted=False, started=True))
        started = time.monotonic()
        self.assertTrue(wait_for(lambda: self.match.last().state == 'running', 2.0))
        self.assertTrue(wait_for(lambda: [g['value'] for g in self.server.snapshot()] == [1, 2], 3.0),
                        [g['value'] for g in self.server.snapshot()])
        self.assertTrue(wait_for(lambda: any(m.path.endswith('/BODY') and m.active_states == ['LEG_2']
                                             for _, m in self.status.since(started)), 2.0),
                        'introspection never showed LEG_2 active')
        # The structure is re-published every 2 s for late viewers.
        body = wait_for(lambda: [m for _, m in self.structure.since(0) if m.path.endswith('/BODY')], 3.0, 0.1)
        self.assertTrue(body, 'no structure for the body: %s' % sorted({m.path for _, m in self.structure.since(0)}))
        self.assertEqual(set(body[0].children), {'LEG_1', 'LEG_2', 'LEG_3'})

        # 3. An obstacle: the trigger preempts LEG_2 (its goal cancelled) and stops the wheels.
        time.sleep(0.5)
        t_obstacle = time.monotonic()
        stop_flag = threading.Event()

        def flag():
            while not stop_flag.is_set():
                self.obstacle.publish(Bool(True))
                time.sleep(0.1)
        threading.Thread(target=flag, daemon=True).start()
        leg2 = wait_for(lambda: self.server.snapshot()[1]['cancelled'], 1.0)
        self.assertTrue(leg2, 'the goal of the interrupted state was not cancelled')
        self.assertLess(leg2 - t_obstacle, 0.4, 'cancel %.3f s after the obstacle' % (leg2 - t_obstacle))
        zero = [t for t, m in self.cmd_vel.since(t_obstacle) if m.linear.x == 0.0 and m.angular.z == 0.0]
        self.assertTrue(zero, 'no zero speed on /hal/drive/cmd_vel')
        self.assertLess(zero[0] - t_obstacle, 0.4)
        self.assertTrue(wait_for(lambda: any(m.active_states == ['topic_flag'] for _, m in self.status.since(t_obstacle)), 1.0),
                        'the handler never showed as active')
        time.sleep(1.0)
        self.assertEqual(len(self.server.snapshot()), 2, 'a goal was sent while the obstacle was there')

        # 4. The obstacle leaves: the interrupted state (LEG_2) resumes, not the machine's start.
        stop_flag.set()
        self.obstacle.publish(Bool(False))
        self.assertTrue(wait_for(lambda: len(self.server.snapshot()) == 3, 3.0), 'nothing resumed')
        self.assertEqual(self.server.snapshot()[2]['value'], 2, 'resumed the wrong state')

        # 5. The BrainSlave: one action at a time by ID.
        start_action = rospy.ServiceProxy('/brain/start_action', StartAction)
        self.assertEqual(start_action('w1', 'wait', 'duration: 30').message, 'started')
        self.assertEqual(start_action('w1', 'wait', 'duration: 30').message, 'already running')
        self.assertEqual(start_action('w2', 'wait', 'duration: 30').message, 'replaced w1')
        self.assertFalse(start_action('w3', 'no_such_action', '').accepted)
        time.sleep(0.6)
        st = self.actions.last()
        self.assertEqual((st.id, st.state), ('w2', 'running'))
        self.assertGreater(st.elapsed, 0.3)
        self.assertGreaterEqual(st.progress, 0.0)
        self.assertLessEqual(st.progress, 100.0)

        # 6. The match end, while LEG_2's goal and the slave's action run: every goal
        # cancelled, every effector deactivated through HAL, no goal afterwards.
        self.assertIsNone(self.server.snapshot()[2]['end'])
        self.assertTrue(wait_for(lambda: self.match.last().state == 'ended', DURATION + 2.0, 0.02))
        t_end = started + DURATION
        cancelled = self.server.snapshot()[2]['cancelled']
        self.assertTrue(cancelled, 'the running goal was not cancelled at the match end')
        self.assertLess(abs(cancelled - t_end), 0.5, 'cancelled %.2f s from the match end' % (cancelled - t_end))
        self.assertTrue(wait_for(lambda: self.deactivated.last().data, 1.0), 'effectors not deactivated')
        self.assertTrue(wait_for(lambda: self.match.last().effectors_deactivated, 1.0))
        self.assertTrue(wait_for(lambda: self.actions.last().state == 'preempted', 2.0), self.actions.last())
        time.sleep(1.5)
        self.assertEqual(len(self.server.snapshot()), 3, 'a goal was sent after the match end')
        self.assertTrue(all(g['end'] is not None for g in self.server.snapshot()), 'a goal was left running')
        switch = rospy.ServiceProxy('/brain/switch_strategy', SwitchStrategy)
        res = switch('brain_test_drive')
        self.assertFalse(res.success)
        self.assertIn('over', res.message)
        self.assertFalse(start_action('w4', 'wait', 'duration: 1').accepted)
        # The brain is still up after the match.
        out = subprocess.run(['rosnode', 'ping', '-c', '1', '/brain'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.assertEqual(out.returncode, 0)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'brain_match', BrainMatchTest, sys.argv)
