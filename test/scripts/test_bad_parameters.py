#!/usr/bin/env python3
"""A bad parameter stops a node at start with one clear line naming the parameter."""
import subprocess
import sys
import unittest

import rospy
import rostest


def run_node(pkg, node, name, params, timeout=30):
    """Set the private params of /<name>, start the node, return (exit code, output)."""
    rospy.delete_param('/' + name) if rospy.has_param('/' + name) else None
    for key, value in params.items():
        rospy.set_param('/%s/%s' % (name, key), value)
    p = subprocess.run(['rosrun', pkg, node, '__name:=' + name], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       timeout=timeout)
    return p.returncode, p.stdout.decode(errors='replace')


class BadParametersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_bad_parameters')

    def test_board_rate_must_be_positive(self):
        rc, out = run_node('hcl_drivers', 'hcl_node', 'bad_rate',
                           {'b': {'type': 'ExampleBoard', 'rate': 0, 'endpoint': 'udp://127.0.0.1:27999'}})
        self.assertNotEqual(rc, 0)
        self.assertIn('/bad_rate/b/rate = 0: must be > 0', out)

    def test_board_rate_is_required(self):
        rc, out = run_node('hcl_drivers', 'hcl_node', 'no_rate',
                           {'b': {'type': 'ExampleBoard', 'endpoint': 'udp://127.0.0.1:27999'}})
        self.assertNotEqual(rc, 0)
        self.assertIn('missing required parameter /no_rate/b/rate', out)

    def test_unknown_board_type_lists_allowed_values(self):
        rc, out = run_node('hcl_drivers', 'hcl_node', 'bad_type', {'b': {'type': 'NoSuchBoard', 'rate': 10}})
        self.assertNotEqual(rc, 0)
        self.assertIn("/bad_type/b/type = 'NoSuchBoard': unknown board type; allowed values:", out)
        self.assertIn('ExampleBoard', out)

    def test_bad_endpoint_names_the_parameter(self):
        rc, out = run_node('hcl_drivers', 'hcl_node', 'bad_ep', {'b': {'type': 'ExampleBoard', 'rate': 10,
                                                                        'endpoint': 'udp://127.0.0.1'}})
        self.assertNotEqual(rc, 0)
        self.assertIn('/bad_ep/b/endpoint', out)

    def test_device_rate_must_be_positive(self):
        rc, out = run_node('hal_nodes', 'hal_node', 'bad_device', {'d': {'type': 'ExampleDevice', 'rate': -1}})
        self.assertNotEqual(rc, 0)
        self.assertIn('/bad_device/d/rate = -1: must be > 0', out)

    def test_unknown_device_type_lists_allowed_values(self):
        rc, out = run_node('hal_nodes', 'hal_node', 'bad_device_type', {'d': {'type': 'Nope', 'rate': 5}})
        self.assertNotEqual(rc, 0)
        self.assertIn("unknown device type; allowed values:", out)
        self.assertIn('ExampleDevice', out)

    def test_unknown_strategy_lists_allowed_values(self):
        rc, out = run_node('smart_brain', 'brain', 'bad_brain', {'strategy': 'no_such_strategy'})
        self.assertEqual(rc, 2)
        self.assertIn("parameter ~strategy = 'no_such_strategy': unknown strategy; allowed values:", out)
        self.assertIn('example', out)

    def test_unknown_emulator_type_lists_allowed_values(self):
        rc, out = run_node('robot_sim', 'firmware_host', 'bad_fw', {'x': {'type': 'no_such_firmware'}})
        self.assertNotEqual(rc, 0)
        self.assertIn("unknown emulator type; allowed values:", out)
        self.assertIn('ExampleBoard', out)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'bad_parameters', BadParametersTest, sys.argv)
