"""robot_network.py: who is the robot, who is allowed, and the Python command gate's counting."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src'))
from robot_core.network_settings import COMPONENT, describe_lines, read_network  # noqa: E402
from robot_core.params import ParameterError, Params  # noqa: E402
from robot_core.robot_network import CommandGate, RobotNetwork  # noqa: E402


def network(tree):
    """A Params over computer/network as the nodes and the installer make it."""
    return Params({'network': tree}, '/computer').block('network')


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


class NetworkSettingsTest(unittest.TestCase):
    """computer/network read one way (network_settings.read_network), by the nodes and the installer."""

    def test_defaults_and_values(self):
        self.assertEqual(read_network(network(None)),
                         {'address': '127.0.0.1', 'master_port': 11311, 'robot_hosts': [], 'allow': []})
        self.assertEqual(read_network(network({'address': '10.1.2.1', 'master_port': 11312,
                                               'robot_hosts': ['10.1.2.3'], 'allow': ['10.1.3.0/24']})),
                         {'address': '10.1.2.1', 'master_port': 11312, 'robot_hosts': ['10.1.2.3/32'],
                          'allow': ['10.1.3.0/24']})

    def test_the_network_of_the_settings(self):
        net = RobotNetwork.from_params(network({'address': '10.1.2.1', 'robot_hosts': ['10.1.2.3'],
                                                'allow': ['10.1.3.0/24']}), local=[])
        self.assertTrue(net.is_robot('10.1.2.1'))
        self.assertTrue(net.is_robot('10.1.2.3'))
        self.assertFalse(net.is_robot('10.1.3.7'))
        self.assertTrue(net.trusted('10.1.3.7'))
        self.assertFalse(net.trusted('10.1.4.1'))

    def refused(self, tree, message):
        with self.assertRaises(ParameterError) as caught:
            RobotNetwork.from_params(network(tree), local=[])
        self.assertEqual(len(str(caught.exception).splitlines()), 1, caught.exception)
        self.assertIn(message, str(caught.exception))

    def test_a_bad_value_is_one_line_naming_it(self):
        self.refused({'address': 'robot.local'}, "parameter /computer/network/address: 'robot.local' is not an IPv4")
        self.refused({'address': '0.0.0.0'}, 'parameter /computer/network/address: 0.0.0.0 is not an address')
        self.refused({'master_port': 70000}, 'parameter /computer/network/master_port: 70000 is not a port')
        self.refused({'allow': '10.1.2.2'}, 'parameter /computer/network/allow: must be a list')
        self.refused({'allow': ['10.1.2.2/24']}, "parameter /computer/network/allow: '10.1.2.2/24' is not an IPv4")
        self.refused({'robot_hosts': ['fe80::1']}, "parameter /computer/network/robot_hosts: 'fe80::1' is not")
        self.refused('10.1.2.1', 'parameter /computer/network = ')

    def test_an_unknown_key_is_refused(self):
        self.refused({'adress': '10.1.2.1'}, 'parameter /computer/network/adress: unknown key')

    def test_declarations_have_meanings(self):
        params = network({})
        read_network(params)
        declared = params.declarations()
        self.assertEqual(sorted(declared), ['address', 'allow', 'master_port', 'robot_hosts'])
        for name, d in declared.items():
            self.assertTrue(d.meaning, name)
            self.assertTrue(d.rule, name)
            self.assertFalse(d.required, name)
        lines = describe_lines()
        self.assertEqual(len(lines), len(declared))
        for line in lines:
            fields = line.split('\t')
            self.assertEqual(len(fields), 7, line)
            self.assertEqual(fields[0], COMPONENT)
            self.assertTrue(fields[6], line)


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
