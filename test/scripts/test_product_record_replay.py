#!/usr/bin/env python3
"""Record and replay, as a team uses them after a match:
1. the skeleton robot runs with record:=true: ONE bag appears, closed cleanly on shutdown, with
   HCL state, HAL outputs, /tf_static, /diagnostics, /rosout and no /clock;
2. launch/replay.launch plays it through a fresh HAL (no emulator, no HCL, no brain) on the
   bag's clock: HAL recomputes its outputs from the recorded HCL state, identical to the match's
   for the same input (matched by the board stamp they come from);
3. scripts/match_report.py turns the bag into a PNG and says which topics are absent.
Both launches run against this test's master, one after the other."""
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rosbag
import rospy
import rostest
from hal_nodes.msg import ExampleReading

from test_support import roslaunch, stop  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
RECORD_SECONDS = 8.0


class RecordReplayTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_product_record_replay')
        cls.tmp = tempfile.mkdtemp(prefix='product_bag_')
        cls.bag = os.path.join(cls.tmp, 'match.bag')
        cls.log = open(os.path.join(cls.tmp, 'launch.log'), 'w')
        launch = roslaunch(os.path.join(ROOT, 'launch', 'skeleton.launch'), 'record:=true', 'bag:=' + cls.bag,
                           log=cls.log)
        # Record once the chain runs (the device publishes), then the match "ends".
        try:
            rospy.wait_for_message('/hal/example_device/reading', ExampleReading, timeout=40.0)
            time.sleep(RECORD_SECONDS)
        finally:
            stop(launch)

    @classmethod
    def tearDownClass(cls):
        cls.log.close()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def recorded(self, topic):
        with rosbag.Bag(self.bag) as bag:
            return [m for _, m, _ in bag.read_messages(topics=[topic])]

    def test_1_one_clean_bag_with_the_match(self):
        self.assertTrue(os.path.isfile(self.bag), 'no bag at %s: %s' % (self.bag, os.listdir(self.tmp)))
        self.assertFalse(os.path.exists(self.bag + '.active'), 'the bag was not closed')
        self.assertEqual(sorted(f for f in os.listdir(self.tmp) if '.bag' in f), ['match.bag'])
        with rosbag.Bag(self.bag) as bag:
            topics = bag.get_type_and_topic_info().topics
            duration = bag.get_end_time() - bag.get_start_time()
        for topic in ('/hcl/example_board/state', '/hcl/example_board/lamp_pwm', '/hal/example_device/reading',
                      '/tf_static', '/diagnostics', '/rosout'):
            self.assertIn(topic, topics, 'missing from the bag: %s (has %s)' % (topic, sorted(topics)))
        self.assertNotIn('/clock', topics)
        self.assertGreater(duration, RECORD_SECONDS - 1.0)
        # 50 Hz board over the recorded time: nothing lost on the way to the bag.
        self.assertGreater(topics['/hcl/example_board/state'].message_count, 0.8 * 50 * RECORD_SECONDS)

    def test_2_replay_through_hal_gives_the_same_outputs(self):
        recorded = {m.header.stamp: m.position for m in self.recorded('/hal/example_device/reading')}
        replayed = []
        lock = threading.Lock()

        def cb(msg):
            with lock:
                replayed.append(msg)
        sub = rospy.Subscriber('/hal/example_device/reading', ExampleReading, cb, queue_size=500)
        replay = roslaunch(os.path.join(ROOT, 'launch', 'replay.launch'), 'bag:=' + self.bag, 'robot:=skeleton',
                           'sim:=true', 'through:=hal', log=self.log)  # rviz:=false is the default
        try:
            rc = replay.wait(timeout=60.0)  # the launch ends with the bag, cleanly
        except subprocess.TimeoutExpired:
            self.fail('replay did not end with the bag')
        finally:
            stop(replay)
            sub.unregister()
        self.assertEqual(rc, 0, 'replay.launch did not end cleanly at the bag end')
        with lock:
            got = list(replayed)
        self.assertGreater(len(got), 0.6 * len(recorded), 'replayed %d readings, match had %d' % (len(got), len(recorded)))
        common = [m for m in got if m.header.stamp in recorded]
        sys.stdout.write('replay: %d readings (match: %d), %d from the same board state as in the match\n'
                         % (len(got), len(recorded), len(common)))
        # No minimum for `common`: the device samples the 50 Hz board states with its own 20 Hz
        # timer, whose phase differs between the match and the replay, so which board states it
        # picks coincides only by chance (16 % and 1 of 148 seen). What replay must guarantee is
        # checked for every reading below: it comes from a recorded board state with the identical
        # derived value; readings sharing a board state with the match must equal the match's.
        for m in common:
            self.assertEqual(m.position, recorded[m.header.stamp])
        # Every replayed reading comes from a recorded board state (HAL saw the bag, nothing live).
        board = {m.header.stamp: m.dial_raw for m in self.recorded('/hcl/example_board/state')}
        for m in got:
            self.assertIn(m.header.stamp, board)
            self.assertAlmostEqual(m.position, board[m.header.stamp] / 1023.0, places=9)

    def test_3_match_report_from_the_bag(self):
        png = os.path.join(self.tmp, 'report.png')
        out = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'match_report.py'), self.bag, '-o', png],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=60)
        text = out.stdout.decode()
        self.assertEqual(out.returncode, 0, text)
        self.assertGreater(os.path.getsize(png), 10000)
        absent = [l for l in text.splitlines() if l.startswith('absent topics:')]
        self.assertEqual(len(absent), 1, text)
        self.assertIn('/sim/ground_truth', absent[0])
        self.assertIn('/mcl/pose', absent[0])
        self.assertNotIn('/diagnostics', absent[0])
        self.assertIn('match report: ' + png, text)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_record_replay', RecordReplayTest, sys.argv)
