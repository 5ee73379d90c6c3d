"""The robots' `brain:` config blocks (config/<robot>.yaml) against the code, without ROS:
strategies, match variant, trigger kinds, and every homologation step's action and arguments."""
import inspect
import os
import unittest

import yaml

from smart_brain import actions, triggers
from smart_brain import strategy as strategies
from smart_brain.strategies.match import VARIANTS

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'config')
ROBOTS = ('eurobot2009', 'logion')


class BrainConfigTest(unittest.TestCase):
    def brain(self, robot):
        with open(os.path.join(CONFIG, robot + '.yaml')) as f:
            return yaml.safe_load(f)['brain']

    def test_strategy_and_variant_exist(self):
        for robot in ROBOTS:
            b = self.brain(robot)
            self.assertIn(b['strategy'], strategies.available(), robot)
            self.assertIn(str(b['match_variant']), VARIANTS, robot)
            self.assertIn(b['match']['start'], ('cord', 'immediate'))
            self.assertGreater(b['match']['duration'], 0)

    def test_trigger_kinds_exist(self):
        for robot in ROBOTS:
            for kind in self.brain(robot).get('triggers', {}):
                self.assertIn(kind, triggers.available(), '%s: ~triggers/%s' % (robot, kind))

    def test_homologation_steps_name_real_actions_with_valid_arguments(self):
        for robot in ROBOTS:
            steps = self.brain(robot)['homologation']['steps']
            self.assertGreater(len(steps), 2)
            for i, step in enumerate(steps):
                args = dict(step)
                name = args.pop('action')
                args.pop('attempts', None)
                args.pop('label', None)
                args.pop('on_abort', None)   # a step option of steps.py, not an action argument
                self.assertIn(name, actions.available(), '%s step %d' % (robot, i))
                # The arguments bind to the action's factory (typos fail here, not in a match).
                inspect.signature(actions._ACTIONS[name]).bind(**args)

    def test_homologation_machines_build_from_the_config(self):
        try:
            from hal_nodes.msg import FollowPathAction, GotoAction  # noqa: F401
        except ImportError:
            self.skipTest('hal_nodes driver actions not generated in this build')
        from smart_brain.steps import build_sequence
        from smart_brain.statemachine import Retry
        for robot in ROBOTS:
            steps = self.brain(robot)['homologation']['steps']
            seq = build_sequence(steps, robot)
            seq.check_consistency()
            children = seq.get_children()
            self.assertEqual(len(children), len(steps))
            first = list(children.values())[0]
            self.assertIsInstance(first, Retry)
            self.assertEqual(first.state.action_name, '/hal/driver/go_straight')

    def test_joystick_buttons_name_real_callbacks(self):
        from smart_brain.strategies.joystick import CALLBACKS
        for robot in ROBOTS:
            for button, cb in self.brain(robot)['joystick']['buttons'].items():
                self.assertIn(cb, CALLBACKS, '%s: button %s' % (robot, button))


if __name__ == '__main__':
    unittest.main()
