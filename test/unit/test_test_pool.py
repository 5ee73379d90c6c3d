"""The test pool's rules (robot_tools.testing): which tests start side by side, and the channels
that keep two tests apart, read from the real test files."""
import unittest

from robot_tools.testing.channels import fixed_channels, robot_launches
from robot_tools.testing.pool import admit
from robot_tools.testing.targets import package_dirs, rostest_file


def item(name, load=1.0, ports=(), alone=False):
    return {'target': name, 'load': load, 'ports': set(ports), 'alone': alone}


class AdmitTest(unittest.TestCase):
    def names(self, todo, running=(), jobs=2, budget=1.7):
        return [x['target'] for x in admit(todo, list(running), jobs, budget)]

    def test_light_tests_fill_the_budget_and_the_slots(self):
        todo = [item('a', 0.8), item('b', 0.8), item('c', 0.05)]
        self.assertEqual(self.names(todo), ['a', 'b'])                # two slots
        self.assertEqual(self.names(todo, jobs=3), ['a', 'b', 'c'])   # 1.7 cores: all three fit
        self.assertEqual(self.names([item('a', 1.2), item('b', 0.8), item('c', 0.4)]), ['a', 'c'])  # b would pass the budget

    def test_a_first_test_always_starts_whatever_its_load(self):
        self.assertEqual(self.names([item('big', 1.9)]), ['big'])

    def test_a_test_alone_waits_for_an_empty_pool_and_keeps_it(self):
        heavy = item('heavy', 1.5, alone=True)
        self.assertEqual(self.names([heavy, item('a', 0.1)], running=[item('r', 0.1)]), [])
        self.assertEqual(self.names([heavy, item('a', 0.1)]), ['heavy'])
        self.assertEqual(self.names([item('a', 0.1)], running=[heavy]), [])

    def test_two_tests_sharing_a_channel_never_run_together(self):
        todo = [item('a', 0.2, ['27100']), item('b', 0.2, ['27100']), item('c', 0.2, ['11311'])]
        self.assertEqual(self.names(todo), ['a', 'c'])
        self.assertEqual(self.names(todo[1:], running=[todo[0]]), ['c'])


class ChannelsTest(unittest.TestCase):
    def channels(self, name):
        packages = package_dirs()
        target = 'run_tests_system_tests_rostest_launch_%s.test' % name
        path = rostest_file(target, packages)
        self.assertIsNotNone(path, target)
        return fixed_channels(target, path, packages, robot_launches())

    def test_the_skeleton_tests_share_the_example_boards_port(self):
        # the port is in config/skeleton.sim.yaml, loaded by the robot's launch: not in the .test
        for name in ('skeleton', 'brain_match'):
            self.assertIn('27100', self.channels(name), name)

    def test_a_robot_launch_on_its_default_channels_owns_them(self):
        self.assertTrue(any(c.startswith('skeleton.launch ') for c in self.channels('skeleton')))


if __name__ == '__main__':
    unittest.main()
