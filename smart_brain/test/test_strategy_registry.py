"""The strategy registry, without ROS."""
import unittest

from smart_brain import strategy as strategies
from smart_brain.strategy import Strategy, StrategyError, register


class StrategyRegistryTest(unittest.TestCase):
    def test_example_is_registered(self):
        self.assertIn('example', strategies.available())
        self.assertEqual(strategies.create('example').name, 'example')

    def test_unknown_name_lists_allowed_values(self):
        with self.assertRaises(StrategyError) as ctx:
            strategies.create('no_such_strategy')
        self.assertIn("'no_such_strategy'", str(ctx.exception))
        self.assertIn('example', str(ctx.exception))

    def test_duplicate_names_are_refused(self):
        @register
        class One(Strategy):
            name = 'dup_test'

        with self.assertRaises(ValueError):
            @register
            class Two(Strategy):
                name = 'dup_test'

    def test_nameless_strategy_is_refused(self):
        with self.assertRaises(ValueError):
            @register
            class Nameless(Strategy):
                pass


if __name__ == '__main__':
    unittest.main()
