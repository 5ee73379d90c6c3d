"""The chaos runner's fault schedules and invariants (robot_tools.chaos.faults,
robot_tools.chaos.invariants) on made-up matches: each invariant catches what it must and lets
pass what it must. No ROS master, no simulation."""
import os
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.chaos import faults as chaos_faults
from robot_tools.chaos import invariants as inv
from robot_tools.matches.match_config import robot_config

ISSUE_CLASSES = {'board_silent', 'can_bus_off', 'can_reset', 'can_malformed', 'serial_garbage', 'serial_truncate',
                 'beacon_silent', 'wheel_slip', 'kidnap', 'opponent_blocks', 'kill_hcl', 'kill_hal', 'kill_brain',
                 'stall_hal', 'kill_record'}


class Stamp(object):
    def __init__(self, t):
        self.t = t

    def to_sec(self):
        return self.t


class FakeBag(object):
    def __init__(self, series):
        self.series = series

    def read_messages(self, topics):
        return ((topics[0], None, Stamp(t)) for t in self.series.get(topics[0], []))


class FakeMatch(object):
    """What the invariants read of a Match: topics, their messages' times, poses."""

    def __init__(self, series=None, poses=None):
        self.topics = {t: ('x', len(v)) for t, v in (series or {}).items()}
        self.bag = FakeBag(series or {})
        self._poses = poses or {}

    def poses(self, topic):
        return self._poses.get(topic, [])


def fault(kind, target='', start=10.0, end=12.0, outcome='injected'):
    return dict(kind=kind, target=target, start=start, end=end, outcome=outcome)


class ScheduleTest(unittest.TestCase):
    def setUp(self):
        self.config = robot_config('eurobot2009')
        self.duration = float(self.config['brain']['match']['duration'])

    def test_the_2009_robot_has_every_class_of_the_issue_but_i2c(self):
        self.assertEqual(set(chaos_faults.catalogue(self.config)), ISSUE_CLASSES)

    def test_an_i2c_robot_has_the_nack_storm(self):
        self.assertIn('i2c_nack_storm', chaos_faults.catalogue(robot_config('logion')))

    def test_ten_matches_cover_every_class_spaced_inside_the_match(self):
        schedules = chaos_faults.draw_schedules(self.config, 10, 1, self.duration)
        self.assertEqual(len(schedules), 10)
        self.assertEqual({f['class'] for s in schedules for f in s}, ISSUE_CLASSES)
        for s in schedules:
            times = [f['at'] for f in s]
            self.assertEqual(times, sorted(times))
            self.assertGreaterEqual(min(times), chaos_faults.FIRST)
            self.assertLessEqual(max(times), self.duration - chaos_faults.LAST)
            self.assertTrue(all(b - a >= chaos_faults.SPACING - chaos_faults.JITTER for a, b in zip(times, times[1:])))

    def test_the_seed_decides(self):
        a = chaos_faults.draw_schedules(self.config, 3, 7, self.duration)
        self.assertEqual(a, chaos_faults.draw_schedules(self.config, 3, 7, self.duration))
        self.assertNotEqual(a, chaos_faults.draw_schedules(self.config, 3, 8, self.duration))

    def test_each_fault_names_its_board_or_process(self):
        self.assertEqual(chaos_faults.expected_status(fault('can_bus_off', 'epos')), 'hcl/epos: board')
        self.assertEqual(chaos_faults.expected_status(fault('stall', '/hal')), 'process /hal')
        self.assertEqual(chaos_faults.expected_status(fault('beacon_silent', '1')), 'hcl/beacons: board')
        self.assertIsNone(chaos_faults.expected_status(fault('kidnap')))


class NamedTest(unittest.TestCase):
    def check(self, points, f=None):
        f = f or fault('board_silent', 'motor_board')
        return inv.faults_named(None, [f], 0.0, series={'hcl/motor_board: board': points})

    def test_named_in_time_and_cleared_in_time_passes(self):
        self.assertEqual(self.check([(10.5, 3, 'stale'), (12.5, 0, 'ok')]), [])

    def test_named_too_late(self):
        v = self.check([(11.5, 3, 'stale'), (12.5, 0, 'ok')])
        self.assertEqual(len(v), 1)
        self.assertIn('not named', v[0][1])

    def test_a_warn_does_not_name_it(self):
        self.assertIn('not named', self.check([(10.5, 1, 'slow'), (12.5, 0, 'ok')])[0][1])

    def test_never_cleared(self):
        self.assertIn('not back to OK', self.check([(10.5, 2, 'x'), (14.5, 0, 'ok')])[0][1])

    def test_a_process_fault_is_named_in_wall_seconds(self):
        # process_watch probes on the wall clock: at a factor of 3, named 2.5 s (simulated) after
        # the stall is 0.8 s of wall time.
        stall = fault('stall', '/hal', 10.0, 12.0)
        points = {'process /hal': [(12.5, 2, 'stalled'), (13.0, 0, 'running')]}
        self.assertIn('not named', inv.faults_named(None, [stall], 0.0, series=points)[0][1])
        self.assertEqual(inv.faults_named(None, [dict(stall, factor=3.0)], 0.0, series=points), [])

    def test_the_recorder_down_excuses(self):
        down = fault('kill', '/record', start=9.0, end=13.0)
        self.assertEqual(inv.faults_named(None, [fault('board_silent', 'motor_board'), down], 0.0,
                                          series={'process /record': [(15.0, 0, 'ok')]}), [])


class LostTest(unittest.TestCase):
    def stream(self, start, end, period=0.1, gap=None):
        t, out = start, []
        while t <= end:
            if not (gap and gap[0] < t < gap[1]):
                out.append(t)
            t += period
        return out

    def test_a_gap_is_lost(self):
        m = FakeMatch({'/odom': self.stream(0, 90, gap=(30, 33))})
        v = inv.nothing_lost(m, [], 0.0, 90.0, 0.0, {})
        self.assertEqual(len(v), 1)
        self.assertIn('/odom', v[0][1])

    def test_its_dead_publisher_excuses_a_gap(self):
        m = FakeMatch({'/odom': self.stream(0, 90, gap=(30, 33))})
        self.assertEqual(inv.nothing_lost(m, [fault('kill', '/hal', 30.0, 31.0)], 0.0, 90.0, 0.0, {}), [])

    def test_the_allowance_after_a_restart_is_wall_time(self):
        # Back at 31 s, silent in the bag until 40 s: 9 s simulated. At real time that is more than
        # RESTART_ALLOWANCE; at a factor of 3 the recorder's reconnection takes seconds of wall time.
        m = FakeMatch({'/odom': self.stream(0, 90, gap=(30, 40))})
        kill = fault('kill', '/hal', 30.0, 31.0)
        self.assertEqual(len(inv.nothing_lost(m, [kill], 0.0, 90.0, 0.0, {})), 1)
        self.assertEqual(inv.nothing_lost(m, [dict(kill, factor=3.0)], 0.0, 90.0, 0.0, {}), [])
        # Slower than real time still allows the wall seconds, never fewer.
        self.assertEqual(len(inv.nothing_lost(m, [dict(kill, factor=0.5)], 0.0, 90.0, 0.0, {})), 1)

    # A Logion chaos match: /hal killed 32.3-35.9 s (factor 3.15), then the recorder 38.9-45.1 s
    # (factor 4.45); the rangers' topics are missing from the bag 32.2-52.9 s. Neither restart
    # alone covers that gap, one after the other they do.
    HAL_THEN_RECORDER = [dict(fault('kill', '/hal', 32.284, 35.934), factor=3.15),
                         dict(fault('kill', '/record', 38.931, 45.111), factor=4.45)]

    def test_one_restart_after_another_excuses_the_gap_they_cover(self):
        m = FakeMatch({'/hal/rangers/front': self.stream(0, 90, gap=(32.19, 52.9))})
        self.assertEqual(inv.nothing_lost(m, self.HAL_THEN_RECORDER, 0.0, 90.0, 0.0, {}), [])

    def test_a_gap_beyond_the_restarts_is_still_lost(self):
        m = FakeMatch({'/hal/rangers/front': self.stream(0, 90, gap=(32.19, 52.9))})
        only_hal = self.HAL_THEN_RECORDER[:1]
        self.assertEqual(len(inv.nothing_lost(m, only_hal, 0.0, 90.0, 0.0, {})), 1)
        apart = [self.HAL_THEN_RECORDER[0], dict(fault('kill', '/record', 60.0, 62.0), factor=1.0)]
        m = FakeMatch({'/hal/rangers/front': self.stream(0, 90, gap=(32.19, 61.0))})
        self.assertEqual(len(inv.nothing_lost(m, apart, 0.0, 90.0, 0.0, {})), 1)

    def test_another_dead_process_does_not(self):
        m = FakeMatch({'/odom': self.stream(0, 90, gap=(30, 33))})
        self.assertEqual(len(inv.nothing_lost(m, [fault('kill', '/brain', 30.0, 31.0)], 0.0, 90.0, 0.0, {})), 1)

    def test_the_hcl_dead_starves_the_hal(self):
        m = FakeMatch({'/odom': self.stream(0, 90, gap=(30, 33))})
        self.assertEqual(inv.nothing_lost(m, [fault('kill', '/hcl', 30.0, 31.0)], 0.0, 90.0, 0.0, {}), [])

    def test_the_commands_hal_sends_a_board_pause_with_hal(self):
        # Logion's LEDs (the HMI device's outputs to the I/O expander), silent 8.6 s from a kill of
        # /hal until the respawned HAL's HMI device published again (a Logion chaos match).
        m = FakeMatch({'/hcl/io/outputs': self.stream(0, 90, gap=(41.9, 50.5))})
        self.assertEqual(inv.nothing_lost(m, [dict(fault('kill', '/hal', 41.9, 45.2), factor=2.86)],
                                          0.0, 90.0, 0.0, {}), [])
        self.assertEqual(len(inv.nothing_lost(m, [dict(fault('kill', '/brain', 41.9, 45.2), factor=2.86)],
                                              0.0, 90.0, 0.0, {})), 1)
        self.assertEqual(inv.owner('/hcl/example_board/lamp_pwm'), '/hal')
        self.assertEqual(inv.owner('/hcl/io/inputs'), '/hcl')

    def test_the_i2c_chips_truth_pauses_with_the_hcl_that_asks_for_it(self):
        # An emulated SRF02 ranges (and publishes its truth) when the driver commands it: silent
        # 5.6 s after a kill of /hcl in a Logion chaos match.
        m = FakeMatch({'/sim/ranger_front/range': self.stream(0, 90, gap=(76.3, 81.9)),
                       '/sim/compass/bearing': self.stream(0, 90, gap=(76.3, 81.3))})
        self.assertEqual(inv.nothing_lost(m, [dict(fault('kill', '/hcl', 76.3, 80.3), factor=3.47)],
                                          0.0, 90.0, 0.0, {}), [])
        self.assertEqual(len(inv.nothing_lost(m, [dict(fault('kill', '/hal', 76.3, 80.3), factor=3.47)],
                                              0.0, 90.0, 0.0, {})), 2)

    def test_a_topic_that_stops_before_the_end_is_lost(self):
        m = FakeMatch({'/hcl/joystick/joy': self.stream(0, 45)})
        self.assertEqual(len(inv.nothing_lost(m, [], 0.0, 90.0, 0.0, {})), 1)

    def test_events_are_not_streams(self):
        m = FakeMatch({'/hal/driver/goto/goal': self.stream(0, 10) + [50.0]})
        self.assertEqual(inv.nothing_lost(m, [], 0.0, 90.0, 0.0, {}), [])


class EndAndRecoveryTest(unittest.TestCase):
    def test_effectors_on_after_the_end(self):
        v = inv.match_ends(FakeMatch(), [], 90.0, 0.0, lambda m, end: None)
        self.assertIn('still on', v[0][1])

    def test_hal_dead_at_the_end_commands_nothing(self):
        self.assertEqual(inv.match_ends(FakeMatch(), [fault('kill', '/hal', 89.5, 93.0)], 90.0, 0.0,
                                        lambda m, end: None), [])

    def poses(self, error_after):
        truth = [(t / 10.0, t / 100.0, 1.0, 0.0) for t in range(0, 900)]
        estimate = [(t, x + (error_after(t)), y, a) for t, x, y, a in truth[1:-1]]
        return FakeMatch(poses={'/mcl/pose': estimate, '/sim/ground_truth': truth})

    def test_back_within_five_seconds_passes(self):
        m = self.poses(lambda t: 0.2 if 10.0 <= t < 14.0 else 0.0)
        self.assertEqual(inv.robot_recovers(m, [fault('kidnap', start=10.0, end=10.0)], 90.0, 0.0), [])

    def test_back_after_eight_seconds_fails(self):
        m = self.poses(lambda t: 0.2 if 10.0 <= t < 18.0 else 0.0)
        v = inv.robot_recovers(m, [fault('kidnap', start=10.0, end=10.0)], 90.0, 0.0)
        self.assertIn('not recovered', v[0][1])

    # A chaos match where the recorder is down while the robot recovers (/brain killed 48.2-57.8 s,
    # the recorder killed 56.7 s and back 62.5 s): the bag holds no pose from 56.6 s to 67.0 s, then
    # poses within 2 cm. The bag cannot tell whether it recovered in the gap.
    def recorder_gap(self, error_after):
        truth = [(t / 10.0, t / 100.0, 1.0, 0.0) for t in range(0, 900)]
        estimate = [(t, x + error_after(t), y, a) for t, x, y, a in truth[1:-1] if not 56.6 < t < 67.0]
        return FakeMatch(poses={'/mcl/pose': estimate, '/sim/ground_truth': truth})

    GAP_FAULTS = [fault('kill', '/brain', start=48.2, end=57.8), fault('kill', '/record', start=56.7, end=62.5)]

    def test_the_recorder_down_after_a_fault_is_judged_from_its_first_pose(self):
        m = self.recorder_gap(lambda t: 0.02)
        self.assertEqual(inv.robot_recovers(m, self.GAP_FAULTS, 90.0, 0.0), [])

    def test_still_off_after_the_recorder_is_back_fails(self):
        m = self.recorder_gap(lambda t: 0.2 if t < 75.0 else 0.0)
        v = inv.robot_recovers(m, self.GAP_FAULTS, 90.0, 0.0)
        self.assertTrue(any('not recovered' in text and 'kill /brain' in text for _, text in v), v)


if __name__ == '__main__':
    unittest.main()


class MotorBlindTest(unittest.TestCase):
    """no_motor_runs_blind's rule (blind_samples) on a recorded case it must excuse and cases it
    must catch. The recorded case: eurobot2009 seed 3 on a loaded machine, no fault injected; the
    robot starts turning 24.83 s into the match. The recorder received the board's first non-zero
    PWM (stamped 24.839) at 24.807 and the commands that caused it (stamped 24.833, 24.844) at
    24.864: by receive times the PWM came 1.23 s after the last non-zero command."""
    WATCHDOG, MARGIN = 0.2, 0.1
    WINDOW = 0.25 + WATCHDOG + MARGIN
    # (stamp, bag time, [pwm0, pwm1], command_age) and the commands' (stamp, bag time), as recorded
    SAMPLES = [(24.790, 24.807, [0.0, 0.0], 0.01), (24.839, 24.807, [25.0, -25.0], 0.006),
               (24.853, 24.807, [31.0, -31.0], 0.009), (24.865, 25.126, [42.0, -42.0], 0.01)]
    COMMANDS = [(23.557, 23.557), (24.833, 24.864), (24.844, 24.864), (24.855, 24.864)]  # the non-zero ones

    def test_a_recorder_stamping_late_in_batches_is_no_blind_motor(self):
        by_stamp = sorted(s for s, _ in self.COMMANDS)
        self.assertEqual(inv.blind_samples(self.SAMPLES, by_stamp, self.WINDOW, self.WATCHDOG, self.MARGIN), [])
        # What the rule did with receive times: the false alarm of the chaos run.
        by_bag = [(b, b, p, a) for _, b, p, a in self.SAMPLES]
        caught = inv.blind_samples(by_bag, sorted(b for _, b in self.COMMANDS), self.WINDOW, self.WATCHDOG, self.MARGIN)
        self.assertEqual(len(caught), 2)
        self.assertIn('no non-zero command for 1.25 s', caught[0][1])

    def test_a_pwm_long_after_the_last_command_is_caught(self):
        samples = [(30.0, 30.0, [40.0, 40.0], 0.01), (31.5, 31.5, [40.0, 40.0], 0.01)]
        caught = inv.blind_samples(samples, [29.9], self.WINDOW, self.WATCHDOG, self.MARGIN)
        self.assertEqual([s for s, _ in caught], [31.5])

    def test_a_board_driving_past_its_watchdog_is_caught_from_its_own_account(self):
        # The HAL kept commanding, but the board got no command frame for 0.6 s and still drove.
        samples = [(40.0, 40.0, [40.0, 40.0], 0.6)]
        caught = inv.blind_samples(samples, [39.95], self.WINDOW, self.WATCHDOG, self.MARGIN)
        self.assertEqual(len(caught), 1)
        self.assertIn('after its last command frame', caught[0][1])

    def test_the_hcl_dead_past_the_watchdog_and_the_recorder_down(self):
        samples = [(50.5, 50.5, [40.0, 0.0], None)]
        self.assertEqual(len(inv.blind_samples(samples, [50.4], self.WINDOW, self.WATCHDOG, self.MARGIN,
                                               hcl_dead=[(50.0, 51.0)])), 1)
        self.assertEqual(inv.blind_samples(samples, [], self.WINDOW, self.WATCHDOG, self.MARGIN,
                                           unrecorded=[(50.0, 51.0)]), [])
