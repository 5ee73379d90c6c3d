"""The network guard (robot_description/scripts/network_guard) reports foreign nodes only: a node
the master cannot place (a killed /hal still registered while roslaunch respawns it) is not one,
and every foreign node is a value of the one "network guard" status (no item per node that would
go STALE when the node leaves)."""
import importlib.machinery
import importlib.util
import os
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))


def load(name):
    path = os.path.join(ROOT, 'robot_description', 'scripts', name)
    loader = importlib.machinery.SourceFileLoader(name, path)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader(name, loader))
    loader.exec_module(module)
    return module


class NetworkGuardTest(unittest.TestCase):
    guard = load('network_guard')

    def test_a_node_the_master_cannot_place_is_not_foreign(self):
        self.assertTrue(self.guard.placed('192.168.1.20'))
        self.assertTrue(self.guard.placed('127.0.0.1'))
        self.assertFalse(self.guard.placed('unknown to the master'))
        self.assertFalse(self.guard.placed('unresolved ([Errno -2] Name or service not known)'))
        self.assertFalse(self.guard.placed(''))

    def test_a_foreign_publisher_commands_a_foreign_subscriber_watches(self):
        level, line = self.guard.describe('/intruder', '192.168.1.99',
                                          {'pub': ['/hal/example_device/lamp'], 'sub': [], 'srv': []})
        self.assertEqual(level, 2)
        self.assertIn('192.168.1.99', line)
        self.assertIn('/hal/example_device/lamp', line)
        level, line = self.guard.describe('/laptop', '192.168.1.98', {'pub': [], 'sub': ['/odom'], 'srv': []})
        self.assertEqual(level, 1)
        self.assertIn('watches', line)


if __name__ == '__main__':
    unittest.main()
