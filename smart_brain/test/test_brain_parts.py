"""Brain parts without ROS: the BrainSlave contract, the match timer, trigger debounce,
the strategy registry's built-in strategies."""
import threading
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import SimClock, Sleeper
from smart_brain import strategy as strategies
from smart_brain.match_timer import MatchTimer
from smart_brain.slave import BrainSlave
from smart_brain.statemachine import Trigger, WaitState


class SlaveTest(unittest.TestCase):
    def test_one_action_at_a_time_by_id(self):
        slave = BrainSlave()
        a, b = Sleeper(10.0), Sleeper(10.0)
        self.assertEqual(slave.start('A', a), 'started')
        self.assertTrue(a.started.wait(1.0))
        self.assertEqual(slave.start('A', Sleeper(10.0)), 'already running')
        self.assertEqual(a.runs, 1)
        time.sleep(0.2)
        self.assertEqual(slave.current_id, 'A')
        self.assertGreaterEqual(slave.elapsed(), 0.2)
        self.assertEqual(slave.start('B', b), 'replaced A')
        self.assertEqual(a.preempted, 1)
        self.assertTrue(b.started.wait(1.0))
        self.assertEqual(slave.current_id, 'B')
        self.assertLess(slave.elapsed(), 0.2)
        self.assertEqual(slave.status()[1], 'running')
        self.assertTrue(slave.stop())
        self.assertEqual(slave.status()[1], 'preempted')

    def test_progress_comes_from_the_action_and_is_100_when_done(self):
        class Half(WaitState):
            def progress(self):
                return 50.0
        slave = BrainSlave()
        slave.start('H', Half(0.2))
        time.sleep(0.05)
        self.assertEqual(slave.progress(), 50.0)
        time.sleep(0.3)
        self.assertEqual(slave.progress(), 100.0)
        self.assertEqual(slave.status()[1], 'succeeded')

    def test_same_id_after_the_end_runs_again(self):
        slave = BrainSlave()
        slave.start('X', WaitState(0.01))
        time.sleep(0.1)
        self.assertEqual(slave.start('X', WaitState(0.01)), 'started')


class MatchTimerTest(unittest.TestCase):
    def test_end_comes_once_at_the_duration_after_the_start(self):
        events = []
        ended = threading.Event()
        timer = MatchTimer(0.3, lambda: events.append(('start', time.monotonic())),
                           lambda: (events.append(('end', time.monotonic())), ended.set()))
        time.sleep(0.2)
        self.assertEqual(events, [], 'nothing before the start signal')
        self.assertFalse(timer.started)
        self.assertTrue(timer.start())
        self.assertFalse(timer.start(), 'a second start signal is ignored')
        self.assertTrue(ended.wait(2.0))
        self.assertEqual([e[0] for e in events], ['start', 'end'])
        self.assertAlmostEqual(events[1][1] - events[0][1], 0.3, delta=0.05)
        self.assertTrue(timer.ended)
        self.assertEqual(timer.remaining(), 0.0)

    def test_end_now(self):
        ended = threading.Event()
        timer = MatchTimer(100.0, lambda: None, ended.set)
        timer.start()
        timer.end_now()
        self.assertTrue(ended.wait(1.0))


class MatchTimerOnASimulatedClockTest(unittest.TestCase):
    def make(self, duration=90.0):
        self.clock = SimClock()
        self.ended = threading.Event()
        return MatchTimer(duration, lambda: None, self.ended.set, clock=self.clock, poll=0.002)

    def test_a_stalled_clock_holds_the_match(self):
        timer = self.make()
        timer.start()
        self.clock.set(150.0)                  # 50 simulated seconds in
        self.assertFalse(self.ended.wait(0.3), 'the clock stalls at 50 s: no end, however long the wall waits')
        self.assertAlmostEqual(timer.elapsed(), 50.0, places=6)
        self.assertAlmostEqual(timer.remaining(), 40.0, places=6)
        self.clock.set(189.9)
        self.assertFalse(self.ended.wait(0.1))
        self.clock.set(190.0)
        self.assertTrue(self.ended.wait(1.0), 'ends when the simulated clock reaches the duration')
        self.assertEqual(timer.remaining(), 0.0)
        self.assertAlmostEqual(timer.elapsed(), 90.0, places=6)

    def test_a_fast_clock_ends_the_match_in_less_wall_time(self):
        timer = self.make()
        timer.start()
        t0 = time.monotonic()
        for i in range(1, 91):                 # 90 simulated seconds in ~0.3 wall seconds
            self.clock.set(100.0 + i)
            time.sleep(0.003)
        self.assertTrue(self.ended.wait(1.0))
        self.assertLess(time.monotonic() - t0, 1.5)

    def test_a_jump_forward_ends_at_once_and_a_jump_back_gives_no_time_back(self):
        timer = self.make()
        timer.start()
        self.clock.set(160.0)
        time.sleep(0.05)                       # the timer reads 60 s elapsed
        self.clock.set(120.0)                  # back (a bag loops): the match does not rewind
        time.sleep(0.05)
        self.assertAlmostEqual(timer.elapsed(), 60.0, places=6)
        self.clock.set(1000.0)
        self.assertTrue(self.ended.wait(1.0), 'a jump past the end ends the match')
        self.assertAlmostEqual(timer.elapsed(), 90.0, places=6)

    def test_a_resumed_match_keeps_its_start(self):
        # A brain respawned 50 s into the match starts its timer at the saved start time.
        timer = self.make()
        self.clock.set(150.0)
        self.assertTrue(timer.start(at=100.0))
        self.assertEqual(timer.started_at, 100.0)
        self.assertAlmostEqual(timer.elapsed(), 50.0, places=6)
        self.assertFalse(timer.start(), 'the start signal of the cord does not restart it')
        self.clock.set(190.0)
        self.assertTrue(self.ended.wait(1.0), 'it ends 90 s after the saved start')

    def test_a_match_resumed_after_its_end_ends_at_once(self):
        timer = self.make()
        self.clock.set(300.0)
        timer.start(at=100.0)
        self.assertTrue(self.ended.wait(1.0))
        self.assertEqual(timer.remaining(), 0.0)

    def test_a_saved_start_in_the_future_is_now(self):
        # (the brain refuses a start from another clock; the timer never counts negative time)
        timer = self.make()
        self.clock.set(100.0)
        timer.start(at=120.0)
        self.assertEqual(timer.started_at, 100.0)

    def test_nothing_counts_before_the_start(self):
        timer = self.make()
        self.clock.set(500.0)
        self.assertFalse(self.ended.wait(0.1))
        self.assertEqual(timer.elapsed(), 0.0)
        self.assertEqual(timer.remaining(), 90.0)
        timer.start()
        self.clock.set(589.0)
        self.assertFalse(self.ended.wait(0.1))
        self.clock.set(590.0)
        self.assertTrue(self.ended.wait(1.0))


class TriggerTest(unittest.TestCase):
    def test_debounce_and_holdoff(self):
        cond = {'v': False}
        trig = Trigger('t', lambda: cond['v'], None, debounce=0.1, holdoff=1.0)
        self.assertFalse(trig.update(0.0))
        cond['v'] = True
        self.assertFalse(trig.update(1.0))
        self.assertFalse(trig.update(1.05))
        self.assertTrue(trig.update(1.1))
        trig.handled(1.2)
        self.assertFalse(trig.update(1.5))   # still true, but within the holdoff
        self.assertFalse(trig.update(2.1))
        self.assertTrue(trig.update(2.3))    # held for the debounce again after the holdoff
        self.assertEqual(trig.fired, 2)


class KeypadStrategyTest(unittest.TestCase):
    """Brain._on_hmi: the keypad's strategy choice before the start switches the strategy; the
    first message (the display's preselection) and choices after the start do not."""

    class FakeBrain(object):
        def __init__(self):
            self.timer = MatchTimer(90.0, lambda: None, lambda: None)
            self.start_topic = '/hal/hmi/input'
            self._hmi_strategy = None
            self.ready = True
            self.switches = []

        def request_switch(self, name):
            self.switches.append(name)
            return True, ''

        def _warn_if_not_ready(self):
            pass

    class Input(object):
        def __init__(self, strategy, started=False):
            self.strategy, self.started = strategy, started

    def on_hmi(self, brain, msg):
        import smart_brain.brain as brain_module
        brain_module.Brain._on_hmi(brain, msg)

    def test_only_a_new_choice_before_the_start_switches(self):
        b = self.FakeBrain()
        self.on_hmi(b, self.Input('match'))
        self.assertEqual(b.switches, [], 'the preselection does not override the launch\'s strategy')
        self.on_hmi(b, self.Input('match'))
        self.on_hmi(b, self.Input('homologation'))
        self.assertEqual(b.switches, ['homologation'])
        self.on_hmi(b, self.Input('homologation', started=True))
        self.assertTrue(b.timer.started)
        self.on_hmi(b, self.Input('joystick', started=True))
        self.assertEqual(b.switches, ['homologation'], 'no switch after the start')


class RegistryTest(unittest.TestCase):
    def test_every_strategy_of_the_issue_is_registered(self):
        for name in ('example', 'homologation', 'match', 'match2008', 'match2009', 'joystick'):
            self.assertIn(name, strategies.available())

    def test_only_the_demo_runs_without_the_match_timer(self):
        self.assertFalse(strategies.create('example').timed)
        self.assertTrue(strategies.create('homologation').timed)


if __name__ == '__main__':
    unittest.main()


class ReadinessDiagnosticsTest(unittest.TestCase):
    """What holds the start: every board or device not OK, except those that say they are optional."""

    @staticmethod
    def status(name, level, message, required=None):
        from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
        s = DiagnosticStatus(name=name, level=level, message=message)
        if required is not None:
            s.values.append(KeyValue('required', required))
        return s

    def test_an_optional_board_does_not_hold_the_start(self):
        from diagnostic_msgs.msg import DiagnosticStatus
        from smart_brain.readiness import diagnostics_problems, is_required
        stale = DiagnosticStatus.STALE
        statuses = {}
        for s in (self.status('/Boards/camera', stale, 'cannot open', 'false'),
                  self.status('/Boards/motor_board', stale, 'not answering', 'true'),
                  self.status('/Devices/odometry', DiagnosticStatus.ERROR, 'stale input'),
                  self.status('/Boards/servo_board', DiagnosticStatus.OK, 'ok', 'true')):
            statuses[s.name] = (s.level, s.message, is_required(s))
        self.assertEqual(diagnostics_problems(statuses),
                         ['/Boards/motor_board is STALE: no fresh report (last said: not answering)',
                          '/Devices/odometry is ERROR: stale input'])
        self.assertEqual(diagnostics_problems(statuses, optional=['odometry']),
                         ['/Boards/motor_board is STALE: no fresh report (last said: not answering)'])

    def test_a_loaded_component_that_never_reported_holds_the_start(self):
        from diagnostic_msgs.msg import DiagnosticStatus
        from smart_brain.readiness import diagnostics_problems
        ok = DiagnosticStatus.OK
        statuses = {'/Boards/joystick: board': (ok, 'ok', True), '/Devices/drive: device': (ok, 'ok', True)}
        expected = ['hcl/joystick: board', 'hal/drive: device', 'hal/joystick: device', 'hal/odometry: device']
        # A board and a device of one name are told apart by their kind.
        self.assertEqual(diagnostics_problems(statuses, expected=expected),
                         ['hal/joystick: device is missing: no status on /diagnostics_agg yet',
                          'hal/odometry: device is missing: no status on /diagnostics_agg yet'])
        self.assertEqual(diagnostics_problems(statuses, optional=['joystick'], expected=expected),
                         ['hal/odometry: device is missing: no status on /diagnostics_agg yet'])
        statuses['/Devices/odometry: device'] = statuses['/Devices/joystick: device'] = (ok, 'ok', True)
        self.assertEqual(diagnostics_problems(statuses, expected=expected), [])
