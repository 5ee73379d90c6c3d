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
from diagnostic_msgs.msg import DiagnosticStatus

from test_support import DeviceDiagnostics, Recorder, value, wait_for
from hcl_drivers.msg import ExampleBoardState


class MissingBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_hcl_missing_board')
        cls.bus = rospy.get_param('~i2c_bus')
        cls.diagnostics = DeviceDiagnostics()
        cls.aggregated = DeviceDiagnostics('/diagnostics_agg')
        cls.state = Recorder('/hcl/example_board/state', ExampleBoardState)

    @classmethod
    def tearDownClass(cls):
        if os.path.exists(cls.bus) and os.path.isfile(cls.bus):
            os.remove(cls.bus)

    def compass(self):
        return self.diagnostics.status('hcl/compass')

    def test_1_missing_board_is_stale_with_the_reason(self):
        self.assertTrue(wait_for(lambda: self.compass() is not None, 20.0), 'no status of the compass board')
        s = self.compass()
        self.assertEqual(s.level, DiagnosticStatus.STALE, s.message)
        self.assertIn('cannot open', s.message)
        self.assertIn(self.bus, s.message)
        self.assertEqual(value(s, 'required'), 'false')

    def test_2_node_and_the_other_board_keep_running(self):
        time.sleep(2.0)  # several retries of the missing board
        self.assertTrue(rosnode.rosnode_ping('/hcl', max_count=1), '/hcl stopped')
        n = len(self.state.items)
        self.assertTrue(wait_for(lambda: len(self.state.items) >= n + 20, 5.0), 'the example board stopped polling')
        example = self.diagnostics.wait_for('hcl/example_board', lambda s: s.level == DiagnosticStatus.OK, 10.0,
                                            since=0.0)
        self.assertTrue(example, self.diagnostics.status('hcl/example_board'))
        self.assertGreaterEqual(int(value(self.compass(), 'open attempts') or '0'), 2)

    def test_3_optional_reaches_the_aggregated_tree(self):
        # the brain's readiness reads /diagnostics_agg: the value must survive the aggregator
        self.assertTrue(wait_for(lambda: self.aggregated.status('/Boards/compass') is not None, 10.0),
                        'no /Boards/compass item')
        self.assertEqual(value(self.aggregated.status('/Boards/compass'), 'required'), 'false')

    @unittest.skipUnless(os.geteuid() == 0, 'creating a file in /dev needs root')
    def test_4_board_opens_when_its_channel_appears(self):
        # a plain file opens like /dev/i2c-N (its I2C ioctls then fail): the retry opens the board,
        # which then reports failed exchanges instead of "cannot open"
        with open(self.bus, 'w'):
            pass
        opened = wait_for(lambda: 'cannot open' not in self.compass().message, 5.0)
        self.assertTrue(opened, self.compass().message)
        self.assertNotEqual(self.compass().level, DiagnosticStatus.OK)
        self.assertIsNone(value(self.compass(), 'open attempts'))
        self.assertTrue(rosnode.rosnode_ping('/hcl', max_count=1))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'hcl_missing_board', MissingBoardTest, sys.argv)
