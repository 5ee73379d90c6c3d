#!/usr/bin/env python3
"""A missing optional board degrades, it does not stop the node: its channel cannot be opened, it
is STALE on /diagnostics with the reason and retried; the other board keeps polling; when the
channel appears the board is opened by the next retry."""
import os
import sys
import time
import unittest

import rosnode
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

from hal_test_common import Recorder, wait_for
from hcl_drivers.msg import ExampleBoardState


class Latest(object):
    """The newest status whose name contains `part`, per topic."""

    def __init__(self, topic, part):
        self.part, self.status = part, None
        self.sub = rospy.Subscriber(topic, DiagnosticArray, self._cb, queue_size=20)

    def _cb(self, msg):
        for s in msg.status:
            if self.part in s.name:
                self.status = s


def values(status):
    return {kv.key: kv.value for kv in status.values}


class MissingBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_hcl_missing_board')
        cls.bus = rospy.get_param('~i2c_bus')
        cls.compass = Latest('/diagnostics', 'hcl/compass')
        cls.compass_agg = Latest('/diagnostics_agg', '/Boards/compass')
        cls.example = Latest('/diagnostics', 'hcl/example_board')
        cls.state = Recorder('/hcl/example_board/state', ExampleBoardState)

    @classmethod
    def tearDownClass(cls):
        if os.path.exists(cls.bus) and os.path.isfile(cls.bus):
            os.remove(cls.bus)

    def test_1_missing_board_is_stale_with_the_reason(self):
        self.assertTrue(wait_for(lambda: self.compass.status is not None, 20.0), 'no status of the compass board')
        s = self.compass.status
        self.assertEqual(s.level, DiagnosticStatus.STALE, s.message)
        self.assertIn('cannot open', s.message)
        self.assertIn(self.bus, s.message)
        self.assertEqual(values(s).get('required'), 'false')

    def test_2_node_and_the_other_board_keep_running(self):
        time.sleep(2.0)  # several retries of the missing board
        self.assertTrue(rosnode.rosnode_ping('/hcl', max_count=1), '/hcl stopped')
        n = len(self.state.items)
        self.assertTrue(wait_for(lambda: len(self.state.items) >= n + 20, 5.0), 'the example board stopped polling')
        self.assertTrue(wait_for(lambda: self.example.status is not None and
                                 self.example.status.level == DiagnosticStatus.OK, 10.0),
                        self.example.status and self.example.status.message)
        self.assertGreaterEqual(int(values(self.compass.status).get('open attempts', '0')), 2)

    def test_3_optional_reaches_the_aggregated_tree(self):
        # the brain's readiness reads /diagnostics_agg: the value must survive the aggregator
        self.assertTrue(wait_for(lambda: self.compass_agg.status is not None, 10.0), 'no /Boards/compass item')
        self.assertEqual(values(self.compass_agg.status).get('required'), 'false')

    @unittest.skipUnless(os.geteuid() == 0, 'creating a file in /dev needs root')
    def test_4_board_opens_when_its_channel_appears(self):
        # a plain file opens like /dev/i2c-N (its I2C ioctls then fail): the retry opens the board,
        # which then reports failed exchanges instead of "cannot open"
        with open(self.bus, 'w'):
            pass
        opened = wait_for(lambda: 'cannot open' not in self.compass.status.message, 5.0)
        self.assertTrue(opened, self.compass.status.message)
        self.assertNotEqual(self.compass.status.level, DiagnosticStatus.OK)
        self.assertNotIn('open attempts', values(self.compass.status))
        self.assertTrue(rosnode.rosnode_ping('/hcl', max_count=1))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'hcl_missing_board', MissingBoardTest, sys.argv)
