"""robot_tools.tuning.objective and scripts/tune.py's parameter handling on made-up rows: the
penalties, a broken invariant that sinks a trial, the paired verdict, the declared space of
config/tune/eurobot2009.yaml against the robot's config. No ROS master, no simulation."""
import math
import os
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.tuning import tune
from robot_tools.tuning import objective
from robot_tools.matches.match_rows import MatchRow
from robot_tools.matches.match_config import robot_config

WEIGHTS = {'contact_penalty': 0.5, 'invariant_penalty': 100.0}


def row(ours, contacts=0, violations=(), seed=1):
    fields = {f: None for f in MatchRow._fields}
    fields.update(seed=seed, ours=ours, contacts=contacts, violations=list(violations), errors=[])
    return MatchRow(**fields)


class ObjectiveTest(unittest.TestCase):
    def test_the_score_less_a_penalty_per_contact(self):
        self.assertEqual(objective.match_value(row(9, contacts=2), WEIGHTS), 8.0)
        self.assertEqual(objective.trial_value([row(9), row(3, contacts=4)], WEIGHTS), (9 + 1) / 2.0)

    def test_a_broken_invariant_sinks_the_trial(self):
        clean = [row(3)] * 5
        broken = [row(12)] * 4 + [row(12, violations=['our robot left the table'])]
        self.assertLess(objective.trial_value(broken, WEIGHTS), objective.trial_value(clean, WEIGHTS))
        self.assertLess(objective.trial_value(broken, WEIGHTS), 0.0)

    def test_a_match_that_never_ran_counts_nothing_and_is_broken(self):
        self.assertEqual(objective.match_value(row(None, contacts=None, violations=['lost: KilledWorker']), WEIGHTS),
                         -100.0)

    def test_no_match_is_an_error(self):
        with self.assertRaises(ValueError):
            objective.trial_value([], WEIGHTS)

    def test_the_paired_verdict(self):
        tuned = [row(s) for s in (5, 7, 6, 8)]
        shipped = [row(s) for s in (4, 5, 6, 5)]
        b, s, d, low, high = objective.paired_verdict(tuned, shipped)
        self.assertEqual((b, s, d), (6.5, 5.0, 1.5))
        # differences 1, 2, 0, 3: sd 1.29, t(3) 3.182: half-width 2.05
        self.assertAlmostEqual(high - d, 3.182446 * math.sqrt(5.0 / 3.0) / 2.0, places=4)
        self.assertAlmostEqual(d - low, high - d)
        self.assertLess(low, 0.0, 'four matches cannot tell this from luck')

    def test_one_seed_has_no_interval(self):
        b, s, d, low, high = objective.paired_verdict([row(5)], [row(3)])
        self.assertEqual(d, 2.0)
        self.assertTrue(math.isnan(low) and math.isnan(high))
        self.assertEqual(objective.closing_line(2, b, s, d, low, high),
                         'trials 2 best_score 5.00 baseline_score 3.00 improvement 2.00 ci95 [nan, nan]')

    def test_the_verdict_needs_the_same_seeds(self):
        with self.assertRaises(ValueError):
            objective.paired_verdict([row(1)], [row(1), row(2)])


#: Every robot with a tune file (config/tune/<robot>.yaml).
TUNED = sorted(f[:-len('.yaml')] for f in os.listdir(os.path.join(ROOT, 'config', 'tune')) if f.endswith('.yaml'))


class SpaceTest(unittest.TestCase):
    def test_held_out_seeds_never_overlap_the_trials(self):
        self.assertEqual(tune.held_out_seeds(1, 3, 4), [100001, 100002, 100003, 100004])
        self.assertEqual(tune.held_out_seeds(1, 3, 2, holdout_seed=200001), [200001, 200002])
        self.assertEqual(tune.held_out_seeds(1, 3, 0), [])
        with self.assertRaises(ValueError):
            tune.held_out_seeds(1, 3, 5, holdout_seed=-1)  # -1 .. 3 includes seeds 1-3

    def test_a_verdict_arm_is_tabled_for_the_scoreboard(self):
        import shutil
        import tempfile
        from robot_tools.matches import scoreboard
        folder = tempfile.mkdtemp(prefix='test_tune_')
        try:
            rows = [row(12, seed=7)._replace(opponent='player', theirs=18, wall=40.0, idle=3.5, stalls=0),
                    row(9, seed=8, violations=['our robot left the table'])._replace(opponent='blocker', theirs=0,
                                                                                    wall=41.0, idle=6.0, stalls=1)]
            tune.write_matches_table(os.path.join(folder, 'holdout_best'), 'eurobot2009', rows, 0.0)
            table, violations = scoreboard.read_table(os.path.join(folder, 'holdout_best', 'eurobot2009_matches.txt'))
        finally:
            shutil.rmtree(folder)
        self.assertEqual(violations, 1)
        self.assertEqual([(r['seed'], r['opponent'], r['ours'], r['idle_s'], r['stalls']) for r in table],
                         [(7.0, 'player', 12.0, 3.5, 0.0), (8.0, 'blocker', 9.0, 6.0, 1.0)])

    def test_both_robots_can_be_tuned(self):
        self.assertEqual(TUNED, ['eurobot2009', 'logion'])

    def test_every_declared_parameter_is_the_robots(self):
        for robot in TUNED:
            params, weights = tune.load_space(robot)
            self.assertTrue(params, robot)
            self.assertEqual(set(weights), set(objective.DEFAULTS), robot)

    def test_the_shipped_config_is_the_first_trial(self):
        for robot in TUNED:
            params, _ = tune.load_space(robot)
            config = robot_config(robot)
            point = tune.shipped_point(params, config)
            self.assertIsNotNone(point, '%s: a shipped value lies outside its declared range' % robot)
            values = tune.values_of(params, point)
            for name, value in values.items():
                self.assertEqual(tune.lookup(config, name), value, robot)

    def test_an_overlay_is_nested_as_the_config(self):
        self.assertEqual(tune.overlay_of({'hal/driver/limits/max_linear_speed': 0.4, 'brain/match2009/approach': 0.2}),
                         {'hal': {'driver': {'limits': {'max_linear_speed': 0.4}}}, 'brain': {'match2009': {'approach': 0.2}}})

    def test_the_driver_accepts_every_speed_and_acceleration_in_range(self):
        # The driver refuses a top speed it cannot stop from within avoidance/braking_distance.
        for robot in TUNED:
            params, _ = tune.load_space(robot)
            config = robot_config(robot)
            ranges = {p['name']: p for p in params}
            speed = ranges['hal/driver/limits/max_linear_speed']['high']
            accel = ranges['hal/driver/limits/max_linear_accel']['low']
            self.assertLessEqual(speed ** 2 / (2 * accel), config['hal']['driver']['avoidance']['braking_distance'], robot)


if __name__ == '__main__':
    unittest.main()
