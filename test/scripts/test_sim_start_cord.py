#!/usr/bin/env python3
"""The start cord through the whole simulated 2009 robot (test/launch/sim_start_cord_eurobot2009.test):
the world's cord starts inserted, the servo board driver and the HMI device show it inserted, and
pulling it (the simulator's switch, nothing else) starts the brain's match. Every switch word the
driver publishes must be one the robot's own emulator sent (no frames of another simulation)."""
import time
import unittest

import rospy
import rostest
from hal_nodes.msg import HumanInput
from hcl_drivers.msg import DigitalInputs
from robot_sim.msg import CanFirmware
from robot_sim.srv import SetSwitch
from smart_brain.msg import MatchStatus

from test_support import Recorder, wait_for


def cord_bit(inputs):
    return (inputs.bits >> inputs.names.index('start_cord')) & 1


class StartCordTest(unittest.TestCase):
    def test_cord_starts_the_match(self):
        rospy.init_node('test_sim_start_cord')
        inputs = Recorder('/hcl/servo_board/inputs', DigitalInputs)
        firmware = Recorder('/sim/servo_board/firmware', CanFirmware)
        hmi = Recorder('/hal/hmi/input', HumanInput)
        brain = Recorder('/brain/match_status', MatchStatus)
        self.assertTrue(wait_for(lambda: brain.last() is not None and brain.last().state == 'waiting_for_start', 100.0),
                        'the brain never waited for the start: %s' % brain.last())
        # Inserted at the start, at every layer.
        self.assertTrue(wait_for(lambda: inputs.last() is not None and cord_bit(inputs.last()) == 1, 20.0),
                        'the servo board driver never read the cord inserted: %s' % inputs.last())
        self.assertTrue(wait_for(lambda: hmi.last() is not None and hmi.last().cord_inserted, 10.0),
                        'the HMI device never showed the cord inserted: %s' % hmi.last())
        t0 = time.monotonic()
        self.assertTrue(wait_for(lambda: len(inputs.since(t0)) >= 50, 20.0))
        # Our emulator's switch word has the cord (bit 4) closed, and the driver reads nothing else.
        words = set(int(m.values[list(m.names).index('switches')]) for m in firmware.messages())
        self.assertTrue(all(w & 0x10 for w in words), 'the emulator sent the cord open: %s' % words)
        seen = [m.bits for _, m in inputs.since(t0)]
        self.assertTrue(all(cord_bit(m) == 1 for _, m in inputs.since(t0)),
                        'the driver read the cord open while it was inserted (foreign frames?): %s' % sorted(set(seen)))
        # Pull it: the simulator's switch only (no /brain/start).
        rospy.wait_for_service('/sim/set_switch', 10.0)
        res = rospy.ServiceProxy('/sim/set_switch', SetSwitch)('start_cord', False)
        self.assertTrue(res.ok, res.message)
        self.assertTrue(wait_for(lambda: cord_bit(inputs.last()) == 0, 10.0), 'the driver never read the cord pulled')
        self.assertTrue(wait_for(lambda: hmi.last().started, 10.0), 'the HMI device never reported the start')
        self.assertTrue(wait_for(lambda: brain.last().state == 'running', 10.0),
                        'the cord did not start the match: %s' % brain.last())


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'sim_start_cord_eurobot2009', StartCordTest)
