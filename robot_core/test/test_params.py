"""robot_core.params (the Python nodes' parameter reader), with no master: conversions, the error
line naming the parameter, what it declares for the tables and what it finds no reader asked for."""
import unittest

from robot_core.params import REQUIRED, ParameterError, Params

TREE = {'rate': 10, 'name': 'a', 'on': True, 'ranges': [1, 2], 'match': {'duration': 90.0, 'start': 'cord'},
        'cost': {'speed': 0.3}, 'other': {'x': 1}, 'typo': 3}


class ParamsTest(unittest.TestCase):
    def params(self, tree=None):
        return Params(dict(TREE) if tree is None else tree, '/brain')

    def test_values_convert_and_defaults_apply(self):
        p = self.params()
        self.assertEqual(p.value('rate', 5.0, float), 10.0)
        self.assertIsInstance(p.value('rate', 5.0, float), float)
        self.assertEqual(p.value('missing', 5.0, float), 5.0)
        self.assertIs(p.value('on', False, bool), True)
        self.assertEqual(p.value('ranges', [], list), [1, 2])
        self.assertEqual(p('name', 'b'), 'a')
        self.assertEqual(p.block('match').positive('duration', 1.0), 90.0)
        self.assertEqual(p.block('absent').value('x', 2, int), 2)

    def test_a_wrong_value_is_one_line_naming_it(self):
        p = self.params({'rate': 0, 'name': [1], 'on': 'yes', 'n': 1.5, 'm': {'start': 'rope'}, 'b': 3})
        cases = [(lambda: p.positive('rate', 1.0), "parameter /brain/rate = 0: must be a number > 0"),
                 (lambda: p.value('name', '', str), "parameter /brain/name = [1]: must be a string"),
                 (lambda: p.value('on', False, bool), "parameter /brain/on = 'yes': must be a boolean"),
                 (lambda: p.value('n', 1, int), "parameter /brain/n = 1.5: must be an integer"),
                 (lambda: p.block('m').value('start', 'cord', str, allowed=('cord', 'immediate')),
                  "parameter /brain/m/start = 'rope': allowed values: cord, immediate"),
                 (lambda: p.block('b'), "parameter /brain/b = 3: must be a dictionary"),
                 (lambda: p.value('absent', REQUIRED, float), 'missing required parameter /brain/absent')]
        for read, message in cases:
            with self.assertRaises(ParameterError) as e:
                read()
            self.assertEqual(str(e.exception), message)

    def test_a_boolean_is_not_a_number(self):
        with self.assertRaises(ParameterError):
            self.params({'rate': True}).value('rate', 1.0, float)

    def test_declarations_for_the_table(self):
        p = self.params()
        p.value('rate', 10.0, float, rule='> 0', meaning='[Hz] how often')
        p.block('match').value('start', 'cord', str, allowed=('cord', 'immediate'))
        p.value('timed', True, bool, default_named="the strategy's `timed`")
        with self.assertRaises(ParameterError):
            p.value('must', REQUIRED, str)
        p.describe('later', 'described before it is read')
        p('later', [])
        d = p.declarations()
        self.assertEqual(d['rate'], ('number', False, '10.0', '> 0', '[Hz] how often'))
        self.assertEqual(d['match/start'].rule, 'one of: cord, immediate')
        self.assertEqual(d['timed'].default, "the strategy's `timed`")
        self.assertTrue(d['must'].required)
        self.assertEqual(d['later'], ('list', False, '[]', '', 'described before it is read'))
        self.assertEqual(p.block('match').declarations()['start'].type, 'string')

    def test_unasked_finds_what_no_reader_knows(self):
        p = self.params()
        p.value('rate', 1.0, float)
        p('name', '')
        p.value('on', False, bool)
        p.value('ranges', [], list)
        p.block('match').value('duration', 1.0, float)
        p('cost', {})           # read whole: its keys are its reader's business
        p.unused('other')       # left alone on purpose
        self.assertEqual(p.unasked(), ["/brain/match/start = 'cord'", '/brain/typo = 3'])
        self.assertEqual(p.block('match').unasked(), ["/brain/match/start = 'cord'"])

    def test_a_dictionary_of_named_blocks_is_declared_by_name(self):
        p = self.params({'zones': {'north': {'x': 1.0, 'typo': 2}, 'south': {}}})
        names = p.block_names('zones')
        self.assertEqual(names, ['north', 'south'])  # the config's order
        for name in names:
            p.block('zones').block(name).value('x', 0.0, float, meaning='[m] where')
        d = p.declarations()
        self.assertEqual(sorted(d), ['zones', 'zones/<name>/x'])
        self.assertEqual(d['zones'].type, 'dictionary of named blocks')
        self.assertEqual(d['zones/<name>/x'], ('number', False, '0.0', '', '[m] where'))
        self.assertEqual(p.unasked(), ['/brain/zones/north/typo = 2'])
        for tree, message in (({'zones': [1]}, 'parameter /brain/zones = [1]: must be a dictionary of named blocks'),
                              ({'zones': {'east': 3}}, 'parameter /brain/zones/east = 3: must be a dictionary')):
            with self.assertRaises(ParameterError) as e:
                self.params(tree).block_names('zones')
            self.assertEqual(str(e.exception), message)


if __name__ == '__main__':
    unittest.main()
