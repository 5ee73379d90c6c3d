"""The brain's parameters read from the shipped configs as the brain reads them at start
(smart_brain/brain_config.py), without ROS: every value known to a reader and described, a typo
found at every level, a wrong value refused with one line naming it."""
import copy
import os
import unittest

import yaml
from robot_core.params import ParameterError
from smart_brain import strategy as strategies
from smart_brain import triggers as trigger_kinds
from smart_brain.brain_config import read_config, read_unconfigured, unknown
from smart_brain.strategy import StrategyError

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'config')
ROBOTS = ('eurobot2009', 'logion', 'skeleton')


def config(robot):
    with open(os.path.join(CONFIG, robot + '.yaml')) as f:
        return yaml.safe_load(f)


class BrainParametersTest(unittest.TestCase):
    def test_the_shipped_configs_hold_no_unknown_key_and_every_read_is_described(self):
        for robot in ROBOTS:
            tree = config(robot)
            params, settings = read_config(tree['brain'], tree.get('table', {}))
            self.assertEqual(unknown(params), [], robot)
            declared = params.declarations()
            self.assertIn('rate', declared, robot)
            for name, d in declared.items():
                self.assertTrue(d.meaning, '%s: /brain/%s is read without a meaning' % (robot, name))
                self.assertTrue(d.type, '%s: /brain/%s is described but never read' % (robot, name))

    def test_every_strategy_block_present_is_read(self):
        params, settings = read_config(config('eurobot2009')['brain'], config('eurobot2009')['table'])
        names = {n.split('/')[0] for n in params.declarations()}
        for block in ('match2009', 'calibration', 'homologation', 'joystick', 'triggers', 'match'):
            self.assertIn(block, names)
        self.assertEqual(settings.strategy.name, 'match')
        self.assertEqual(settings.strategy.impl.name, 'match2009')

    def test_a_typo_is_found_at_every_level(self):
        tree = config('eurobot2009')
        brain = copy.deepcopy(tree['brain'])
        brain['rat'] = 10
        brain['match']['duratoin'] = 90
        brain['match2009']['aproach'] = 0.2
        brain['calibration']['round'] = 2
        params, _ = read_config(brain, tree['table'])
        self.assertEqual(unknown(params), [
            'parameter /brain/calibration/round = 2: no reader knows it',
            'parameter /brain/match/duratoin = 90: no reader knows it',
            'parameter /brain/match2009/aproach = 0.2: no reader knows it',
            'parameter /brain/rat = 10: no reader knows it'])

    def test_a_trigger_typo_or_a_wrong_value_stops_the_reading_naming_it(self):
        tree = config('eurobot2009')
        cases = [(('rate',), 0, ParameterError, 'parameter /brain/rate = 0: must be a number > 0'),
                 (('match', 'start'), 'rope', ParameterError,
                  "parameter /brain/match/start = 'rope': allowed values: cord, immediate"),
                 (('triggers', 'opponent_ahead', 'distance'), 'far', ParameterError,
                  "parameter /brain/triggers/opponent_ahead/distance = 'far': must be a number"),
                 (('triggers', 'stuck', 'debounse'), 0.3, StrategyError,
                  'parameter ~triggers/stuck: unknown key(s) debounse'),
                 (('joystick', 'max_linear'), 'fast', ParameterError,
                  "parameter /brain/joystick/max_linear = 'fast': must be a number"),
                 (('strategy_modules',), [3], ParameterError,
                  'parameter /brain/strategy_modules = [3]: must be a list of Python module names'),
                 (('match_variant',), '2010', ParameterError,
                  "parameter /brain/match_variant = '2010': allowed values: 2008, 2009")]
        for path, value, error, message in cases:
            brain = copy.deepcopy(tree['brain'])
            block = brain
            for key in path[:-1]:
                block = block[key]
            block[path[-1]] = value
            with self.assertRaises(error) as e:
                read_config(brain, tree['table'])
            self.assertEqual(str(e.exception), message, path)

    def test_a_strategy_given_by_the_caller_replaces_the_configs(self):
        # check_config --strategy / make run STRATEGY=: the config's own is not an unknown key
        tree = config('eurobot2009')
        params, settings = read_config(tree['brain'], tree['table'], 'idle')
        self.assertEqual(settings.strategy.name, 'idle')
        self.assertEqual(unknown(params), [])
        del tree['brain']['strategy']
        self.assertEqual(read_config(tree['brain'], tree['table'], 'idle')[1].strategy.name, 'idle')

    def test_the_match_timer_block_is_not_the_match_strategy(self):
        # a robot of its own with a match duration and no match_variant: nothing asks for a variant
        brain = {'strategy': 'idle', 'match': {'duration': 100}}
        params, settings = read_config(brain, {})
        self.assertEqual(settings.duration, 100.0)
        self.assertEqual(unknown(params), [])

    def test_the_table_read_once_reaches_the_strategy_and_its_triggers(self):
        tree = config('logion')
        tree['table']['length'] = 2.5
        _, settings = read_config(tree['brain'], tree['table'])
        impl = settings.strategy.impl
        self.assertEqual(impl.table, (2.5, tree['table']['width']))
        self.assertEqual(impl.start_zones, tree['table']['start_zones'])
        opponent = [values for kind, _, values in impl.trigger_settings if kind == 'opponent_ahead']
        self.assertEqual(opponent, [dict(opponent[0], table=(2.5, tree['table']['width']))])
        # a config without a table: 3 m x 2.1 m
        self.assertEqual(read_config(tree['brain'], {})[1].strategy.impl.table, (3.0, 2.1))

    def test_a_wrong_table_value_is_refused_naming_it(self):
        tree = config('logion')
        tree['table']['width'] = 'wide'
        with self.assertRaises(ParameterError) as e:
            read_config(tree['brain'], tree['table'])
        self.assertEqual(str(e.exception), "parameter /table/width = 'wide': must be a number")

    def test_what_a_config_does_not_set_up_is_described_at_its_defaults(self):
        # check_brain_config --describe: a parameter table for every strategy and trigger kind
        params, _ = read_config({'strategy': 'idle'}, {})
        declared = read_unconfigured(params, {}).declarations()
        self.assertEqual({name.split('/')[1] for name in declared if name.startswith('triggers/')},
                         set(trigger_kinds.available()))
        self.assertIn('topic_flag', trigger_kinds.available())
        self.assertEqual(declared['triggers/topic_flag/topic'].default, '/brain/stop_flag')
        self.assertTrue(declared['calibration/square'].required)
        self.assertEqual(declared['calibration/rounds'].default, '1')
        for name, d in declared.items():
            self.assertTrue(d.meaning, '/brain/%s is read without a meaning' % name)
            self.assertTrue(d.type, '/brain/%s is described but never read' % name)
        # what the config sets up is described by its own reading, not again
        tree = config('eurobot2009')
        params, _ = read_config(tree['brain'], tree['table'])
        declared = read_unconfigured(params, tree['table']).declarations()
        self.assertEqual({name.split('/')[0] for name in declared} & set(strategies.available()), {'match2008'})
        self.assertEqual({name.split('/')[1] for name in declared if name.startswith('triggers/')}, {'topic_flag'})

    def test_a_missing_strategy_names_the_allowed_ones(self):
        with self.assertRaises(StrategyError) as e:
            read_config({'rate': 10}, {})
        self.assertIn('missing required parameter /brain/strategy; allowed values: ', str(e.exception))
        self.assertIn('match2009', str(e.exception))


if __name__ == '__main__':
    unittest.main()
