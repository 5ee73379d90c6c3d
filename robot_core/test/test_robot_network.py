"""robot_network.py: who is the robot, who is allowed, and the Python command gate's counting."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src'))
from robot_core.robot_network import CommandGate, RobotNetwork  # noqa: E402


class FakeMaster(object):
    def __init__(self, uris):
        self.uris, self.calls = uris, 0

    def lookupNode(self, node):
        self.calls += 1
        if node not in self.uris:
            raise Exception('lookupNode: unknown node %s' % node)
        return self.uris[node]


class RobotNetworkTest(unittest.TestCase):
    def test_robot_allowed_and_foreign(self):
        net = RobotNetwork(['10.1.2.1'], ['10.1.2.2', '10.1.3.0/24'], local=[])
        self.assertTrue(net.is_robot('127.0.0.1'))
        self.assertTrue(net.is_robot('10.1.2.1'))
        self.assertFalse(net.is_robot('10.1.2.2'))
        self.assertTrue(net.trusted('10.1.2.2'))
        self.assertTrue(net.trusted('10.1.3.77'))
        self.assertFalse(net.trusted('10.1.2.3'))
        self.assertFalse(net.trusted('unknown to the master'))

    def test_bad_address_is_named(self):
        with self.assertRaisesRegex(ValueError, 'robot.local'):
            RobotNetwork(['robot.local'], local=[])

    def test_host_of_asks_the_master_once(self):
        net = RobotNetwork([], [], local=[])
        master = FakeMaster({'/n': 'http://10.5.5.5:4242/'})
        self.assertEqual(net.foreign(master, '/n'), (True, '10.5.5.5'))
        self.assertEqual(net.foreign(master, '/n'), (True, '10.5.5.5'))
        self.assertEqual(master.calls, 1)
        self.assertEqual(net.foreign(master, '/gone')[0], True)


class CommandGateTest(unittest.TestCase):
    def test_foreign_ignored_during_a_match_only(self):
        running = [False]
        master = FakeMaster({'/laptop': 'http://10.1.2.2:1/', '/intruder': 'http://10.9.9.9:1/',
                             '/brain': 'http://127.0.0.1:1/'})
        gate = CommandGate(RobotNetwork([], ['10.1.2.2'], local=[]), master, lambda: running[0])
        self.assertTrue(gate.accept('/brain', '/x'))
        self.assertTrue(gate.accept('/laptop', '/x'))
        self.assertTrue(gate.accept('/intruder', '/x'))
        running[0] = True
        self.assertTrue(gate.accept('/laptop', '/x'))
        self.assertFalse(gate.accept('/intruder', '/x'))
        (status,) = gate.statuses('/hal')
        self.assertEqual(status.hardware_id, '10.9.9.9')
        self.assertEqual(status.level, 2)
        self.assertEqual({v.key: v.value for v in status.values}, {'ignored': '1', 'obeyed': '1'})


if __name__ == '__main__':
    unittest.main()
