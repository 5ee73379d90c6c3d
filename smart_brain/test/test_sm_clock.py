"""The brain's clock (statemachine/clock.py) in simulation: waits, state timeouts and trigger
hold-offs count simulated seconds, so they last as long at any real-time factor, and a stalled
/clock holds them."""
import threading
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import SimClock
from smart_brain.statemachine import Trigger, WaitState, clock, timers


class ClockTest(unittest.TestCase):
    def setUp(self):
        self.sim = SimClock(1000.0)
        clock.use(self.sim, simulated=True)

    def tearDown(self):
        clock.use_monotonic()

    def run_state(self, state):
        out = {}
        t = threading.Thread(target=lambda: out.setdefault('outcome', state.execute(None)), daemon=True)
        t.start()
        return t, out

    def test_a_wait_lasts_simulated_seconds_and_a_stalled_clock_holds_it(self):
        t, out = self.run_state(WaitState(2.0))
        time.sleep(0.2)
        self.assertTrue(t.is_alive(), 'the clock stands still: 0 of 2 simulated seconds waited')
        self.sim.advance(1.9)
        time.sleep(0.1)
        self.assertTrue(t.is_alive())
        self.sim.advance(0.2)
        t.join(1.0)
        self.assertFalse(t.is_alive(), 'waited past 2 simulated seconds')
        self.assertEqual(out['outcome'], 'succeeded')

    def test_a_fast_clock_ends_a_wait_in_less_wall_time(self):
        t, out = self.run_state(WaitState(10.0))
        started = time.monotonic()
        while t.is_alive() and time.monotonic() - started < 2.0:
            self.sim.advance(0.5)            # 10 simulated seconds in ~0.1 s of wall time
            time.sleep(0.005)
        t.join(1.0)
        self.assertEqual(out.get('outcome'), 'succeeded')
        self.assertLess(time.monotonic() - started, 1.0)

    def test_trigger_debounce_and_holdoff_count_simulated_seconds(self):
        cond = {'v': True}
        trig = Trigger('t', lambda: cond['v'], None, debounce=0.5, holdoff=2.0)
        self.assertFalse(trig.update())
        self.sim.advance(0.4)
        self.assertFalse(trig.update())
        self.sim.advance(0.1)
        self.assertTrue(trig.update(), 'held for the 0.5 s debounce on the simulated clock')
        trig.handled()
        self.sim.advance(1.9)
        self.assertFalse(trig.update(), 'within the 2 s hold-off')
        self.sim.advance(0.2)
        self.assertFalse(trig.update(), 'debounce again after the hold-off')
        self.sim.advance(0.5)
        self.assertTrue(trig.update())

    def test_a_timer_fires_on_the_simulated_clock(self):
        fired = threading.Event()
        timers.call_later(3.0, fired.set)
        self.assertFalse(fired.wait(0.2))
        self.sim.advance(3.1)
        self.assertTrue(fired.wait(1.0))

    def test_sleep(self):
        t = threading.Thread(target=lambda: clock.sleep(1.0), daemon=True)
        t.start()
        time.sleep(0.1)
        self.assertTrue(t.is_alive())
        self.sim.advance(1.0)
        t.join(1.0)
        self.assertFalse(t.is_alive())


if __name__ == '__main__':
    unittest.main()
