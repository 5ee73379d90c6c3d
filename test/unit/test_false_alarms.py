"""The false-alarm invariant (robot_tools.matches.false_alarms) on recorded statuses: what it catches (an
ERROR or STALE during the match that no injected fault explains) and what it excuses (the
start-up, the stop, a fault's own status, what is computed from it, within its allowance).
The messages are as the boards, devices and process_watch wrote them in recorded matches."""
import os
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.matches import false_alarms as fa
from robot_tools.matches.match_config import robot_config

OK, WARN, ERROR, STALE = 0, 1, 2, 3
START, END = 3.0, 93.0  # bag times of the start signal and the match end
MOTOR_RTR = 'last exchange failed: motor board (node 10) did not answer the RTRs within 5 ms'
SERVO_RTR = 'last exchange failed: servo board (node 12) did not answer the RTRs within 10 ms'


def fault(kind, target, start, end, factor=1.0, outcome='OK: injected'):
    return dict(kind=kind, target=target, start=start, end=end, factor=factor, outcome=outcome)


class FalseAlarmTest(unittest.TestCase):
    config = robot_config('eurobot2009')

    def alarms(self, series, faults=()):
        return fa.false_alarms(series, START, END, list(faults), START, self.config)

    def test_an_error_in_a_clean_match_is_caught_once_per_episode(self):
        series = {'hcl/motor_board: board': [(10.0, OK, 'ok'), (24.1, ERROR, MOTOR_RTR), (24.2, ERROR, MOTOR_RTR),
                                             (24.3, OK, 'ok'), (50.0, STALE, 'no exchange for 0.3 s')],
                  'hal/odometry: device': [(10.0, OK, 'ok'), (24.2, WARN, 'encoder left: 1 stale read')]}
        found = self.alarms(series)
        self.assertEqual(len(found), 2, found)
        self.assertAlmostEqual(found[0][0], 21.1)
        self.assertIn('"hcl/motor_board: board" ERROR at 21.1 s', found[0][1])
        self.assertIn('did not answer the RTRs', found[0][1])
        self.assertIn('STALE at 47.0 s', found[1][1])
        self.assertEqual(fa.count([(0, t) for _, t in found] + [(0, 'lost: x')]), 2)

    def test_start_up_and_stop_are_excused(self):
        series = {'hal/beacons: device': [(0.5, ERROR, 'no beacon delta for inf s'), (2.9, OK, 'ok')],
                  'hal/drive: device': [(93.5, ERROR, 'effectors deactivated'), (95.0, STALE, 'stopping')]}
        self.assertEqual(self.alarms(series), [])

    def test_a_board_fault_excuses_its_board_and_the_devices_not_another_board(self):
        f = fault('board_silent', 'motor_board', 20.0, 22.0)
        series = {'hcl/motor_board: board': [(20.1, ERROR, 'board (node 10) not answering')],
                  'hal/odometry: device': [(20.3, ERROR, 'no fresh encoder counts')],
                  'hal/localization: device': [(26.5, ERROR, 'odometry stale')],  # within 5 s of the end
                  'hcl/servo_board: board': [(20.5, ERROR, SERVO_RTR)]}
        found = self.alarms(series, [f])
        self.assertEqual([t.split('"')[1] for _, t in found], ['hcl/servo_board: board'], found)
        # Its own status back late: no longer this fault's doing.
        late = {'hcl/motor_board: board': [(20.1, ERROR, 'x'), (21.0, OK, 'ok'), (25.0, ERROR, MOTOR_RTR)]}
        self.assertEqual(len(self.alarms(late, [f])), 1)

    def test_a_bus_off_excuses_every_board_on_the_bus(self):
        f = fault('can_bus_off', 'epos', 30.0, 32.0)
        series = {'hcl/%s: board' % b: [(30.2, ERROR, 'CAN bus is bus-off')] for b in fa.can_boards(self.config)}
        series['hcl/beacons: board'] = [(30.4, ERROR, 'no frame')]  # serial: not on the bus
        found = self.alarms(series, [f])
        self.assertEqual([t.split('"')[1] for _, t in found], ['hcl/beacons: board'])
        self.assertGreaterEqual(len(fa.can_boards(self.config)), 5)

    def test_a_report_one_clock_step_before_the_fault_is_its(self):
        # The simulator applies the fault before it publishes the step's /clock: the board's
        # ERROR is stamped with the previous one (as recorded: 1 ms before the start).
        f = fault('can_bus_off', 'stepper_board', 30.0, 32.0)
        early = {'hcl/epos: board': [(29.999, ERROR, 'CAN bus is bus-off')]}
        self.assertEqual(self.alarms(early, [f]), [])
        before = {'hcl/epos: board': [(29.5, ERROR, 'CAN bus is bus-off')]}  # not a clock step: before it
        self.assertEqual(len(self.alarms(before, [f])), 1)

    def test_a_killed_process_excuses_what_runs_on_it_in_wall_seconds(self):
        kill_hcl = fault('kill', '/hcl', 40.0, 41.0, factor=3.0)
        series = {'process /hcl': [(40.1, ERROR, 'gone')],
                  'hal/drive: device': [(60.0, STALE, 'no fresh state')],        # 10 s wall at factor 3 + 5 s
                  'hcl/epos: board': [(80.0, ERROR, 'did not answer')],           # long after
                  'network guard': [(40.5, ERROR, 'foreign node /hcl commands the robot')]}
        found = self.alarms(series, [kill_hcl])
        self.assertEqual(sorted(t.split('"')[1] for _, t in found), ['hcl/epos: board', 'network guard'])
        kill_brain = fault('kill', '/brain', 50.0, 51.0)
        series = {'process /brain': [(50.2, ERROR, 'gone')], 'hal/odometry: device': [(50.5, ERROR, 'x')]}
        self.assertEqual([t.split('"')[1] for _, t in self.alarms(series, [kill_brain])], ['hal/odometry: device'])

    def test_world_faults_excuse_the_devices_that_see_them(self):
        series = {'hal/localization: device': [(61.0, ERROR, 'lost: best cluster 0.2 of the weight')],
                  'hal/vision: device': [(61.5, ERROR, 'Lookup would require extrapolation 0.002 s into the future')]}
        found = self.alarms(series, [fault('kidnap', '', 60.0, 60.0)])
        self.assertEqual([t.split('"')[1] for _, t in found], ['hal/vision: device'])

    def test_a_refused_fault_explains_nothing(self):
        series = {'hcl/motor_board: board': [(20.1, ERROR, 'x')]}
        refused = fault('board_silent', 'motor_board', 20.0, 22.0, outcome='REFUSED: no such board')
        self.assertEqual(len(self.alarms(series, [refused])), 1)


if __name__ == '__main__':
    unittest.main()
