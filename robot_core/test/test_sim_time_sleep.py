"""robot_core.sim_time_sleep: rospy's sleeps on simulated time end on the clock message that
reaches their deadline, not before, and are not woken by the messages in between; time moving
backwards raises as rospy does; rospy.Rate and rospy.Timer go through it. No master: the test
sets ROS time itself, as rospy's /clock subscriber does."""
import threading
import time
import unittest

import rospy
import rospy.exceptions
import rospy.rostime

from robot_core import sim_time_sleep

sim_time_sleep.install()
rospy.rostime.set_rostime_initialized(True)


def set_time(sec):
    rospy.rostime._set_rostime(rospy.Time.from_sec(sec))


def set_time_ms(ms):
    """100 s + ms, exactly (100.0 + ms * 0.001 as a float may fall a nanosecond short)."""
    rospy.rostime._set_rostime(rospy.Time(100 + ms // 1000, (ms % 1000) * 1000000))


def wait_until(pred, timeout=2.0):
    # Wall time on purpose: it waits for the sleeper threads, which the OS runs on wall time; ROS
    # time is what the test sets by hand.
    end = time.time() + timeout
    while not pred() and time.time() < end:
        time.sleep(0.001)
    return pred()


class Sleeper(threading.Thread):
    def __init__(self, duration):
        super(Sleeper, self).__init__(daemon=True)
        self.duration, self.woke_at, self.error = duration, None, None
        self.start()

    def run(self):
        try:
            rospy.sleep(self.duration)
            self.woke_at = rospy.get_rostime().to_sec()
        except Exception as e:  # noqa: BLE001 (the test looks at which)
            self.error = e


class SimTimeSleepTest(unittest.TestCase):
    def setUp(self):
        set_time(100.0)
        self.cond = rospy.rostime.get_rostime_cond()
        self.assertIsInstance(self.cond, sim_time_sleep.DeadlineCondition)

    def pending(self):
        with self.cond:
            return len(self.cond._deadlines)

    def test_wakes_on_the_clock_message_that_reaches_its_deadline(self):
        s = Sleeper(0.5)
        self.assertTrue(wait_until(lambda: self.pending() == 1), 'the sleeper never registered its deadline')
        for ms in range(1, 500):  # 499 clock messages before the deadline
            set_time_ms(ms)
        time.sleep(0.05)
        self.assertTrue(s.is_alive(), 'woke before its deadline')
        self.assertEqual(self.pending(), 1, 'the sleeper was woken by clock messages before its deadline')
        set_time(100.5)
        s.join(2.0)
        self.assertFalse(s.is_alive())
        self.assertIsNone(s.error)
        self.assertAlmostEqual(s.woke_at, 100.5, places=6)

    def test_a_clock_message_past_the_deadline_wakes_it(self):
        s = Sleeper(rospy.Duration(0.2))
        self.assertTrue(wait_until(lambda: self.pending() == 1))
        set_time(101.0)
        s.join(2.0)
        self.assertFalse(s.is_alive())
        self.assertAlmostEqual(s.woke_at, 101.0, places=6)

    def test_several_sleepers_each_at_its_own_deadline(self):
        sleepers = [Sleeper(d) for d in (0.3, 0.1, 0.2)]
        self.assertTrue(wait_until(lambda: self.pending() == 3))
        set_time(100.15)
        self.assertTrue(wait_until(lambda: not sleepers[1].is_alive()))
        self.assertTrue(sleepers[0].is_alive() and sleepers[2].is_alive())
        set_time(100.301)  # (100.3 as a float is a nanosecond short of 100 s + 0.3 s)
        for s in sleepers:
            s.join(2.0)
            self.assertFalse(s.is_alive())

    def test_time_moving_backwards_raises(self):
        s = Sleeper(1.0)
        self.assertTrue(wait_until(lambda: self.pending() == 1))
        set_time(50.0)
        s.join(2.0)
        self.assertFalse(s.is_alive())
        self.assertIsInstance(s.error, rospy.exceptions.ROSTimeMovedBackwardsException)

    def test_a_stalled_clock_keeps_one_entry_per_sleeper(self):
        s = Sleeper(0.5)
        self.assertTrue(wait_until(lambda: self.pending() == 1))
        time.sleep(1.2)  # two of the sleeper's shutdown polls without a clock message
        self.assertEqual(self.pending(), 1)
        set_time(100.6)
        s.join(2.0)
        self.assertFalse(s.is_alive())
        self.assertEqual(self.pending(), 0)

    def test_zero_and_negative_durations_return_at_once(self):
        start = time.time()  # wall: "at once" means the call did not block, whatever ROS time does
        rospy.sleep(0.0)
        rospy.sleep(-1.0)
        self.assertLess(time.time() - start, 0.5)

    def test_rate_and_timer_sleep_through_it(self):
        fired = []
        timer = rospy.Timer(rospy.Duration(0.1), lambda event: fired.append(event))
        try:
            self.assertTrue(wait_until(lambda: self.pending() >= 1))
            for ms in range(1, 351):
                set_time_ms(ms)
                if ms % 100 == 0:  # a deadline: the next message waits for the callback, as a slow clock would
                    self.assertTrue(wait_until(lambda: len(fired) == ms // 100), (ms, fired))
            self.assertEqual([round(e.current_expected.to_sec(), 6) for e in fired[:3]], [100.1, 100.2, 100.3])
            for e in fired[:3]:
                self.assertEqual(e.current_real, e.current_expected)  # on the clock message of its deadline
        finally:
            timer.shutdown()
            set_time(200.0)  # its last sleep ends
            time.sleep(0.05)

if __name__ == '__main__':
    unittest.main()
