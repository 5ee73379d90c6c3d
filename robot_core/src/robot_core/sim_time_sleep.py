"""rospy's sleeps on simulated time, woken once at their deadline instead of at every /clock.

On simulated time rospy.sleep, rospy.Rate and rospy.Timer wait on one condition that the /clock
subscriber notifies at every clock message: with /clock at up to 1 kHz, every sleeping thread of
a node wakes up to a thousand times a second only to see that its deadline has not come. In the
brain that was three threads at ~1,600 wake-ups a second each.

install() (before the node's threads start sleeping) gives rospy a condition that also keeps the
sleepers' deadlines: the /clock callback, which already holds its lock, wakes exactly the sleepers
whose deadline the new time reached, and every sleeper when time moved backwards or switched to
the wall clock. A sleep ends on the same clock message as before, with the same exceptions
(ROSInterruptException at shutdown, ROSTimeMovedBackwardsException); on wall time nothing changes.
"""
import heapq
import itertools
import threading

import genpy
import rospy
import rospy.core
import rospy.exceptions
import rospy.rostime
import rospy.timer

_SHUTDOWN_POLL = 0.5  # [s, wall] as rospy: a sleeper checks for shutdown at least this often


class DeadlineCondition(threading.Condition):
    """rospy's time condition, plus the deadlines of the sleepers waiting for a simulated time."""

    def __init__(self):
        super(DeadlineCondition, self).__init__()
        self._deadlines = []  # heap of (deadline [ns], order, threading.Event)
        self._order = itertools.count()
        self._last = None  # [ns] the time of the previous notification

    def wake_at(self, deadline, event):
        """Sets `event` once ROS time reaches `deadline` (genpy.Time). Call with the lock held."""
        if rospy.rostime.get_rostime() >= deadline:
            event.set()
        else:
            heapq.heappush(self._deadlines, (deadline.to_nsec(), next(self._order), event))

    def notify_all(self):
        # rospy calls it with the lock held, once the new time is set.
        now = rospy.rostime._rostime_current  # None: back on the wall clock
        now_ns = None if now is None else now.to_nsec()
        if now_ns is None or (self._last is not None and now_ns < self._last):
            self._wake_all()  # every sleeper looks again, then raises or sleeps on
        else:
            while self._deadlines and self._deadlines[0][0] <= now_ns:
                heapq.heappop(self._deadlines)[2].set()
        self._last = now_ns
        super(DeadlineCondition, self).notify_all()  # other waiters (the wait for the first clock)

    notifyAll = notify_all

    def wake_everyone(self):
        with self:
            self._wake_all()

    def _wake_all(self):  # with the lock held
        while self._deadlines:
            heapq.heappop(self._deadlines)[2].set()


_wall_sleep = rospy.timer.sleep  # rospy's own, for wall time


def sleep(duration):
    """rospy.sleep with the same contract; on simulated time the thread wakes at its deadline."""
    if rospy.rostime.is_wallclock():
        return _wall_sleep(duration)
    cond = rospy.rostime.get_rostime_cond()
    if not isinstance(cond, DeadlineCondition):
        return _wall_sleep(duration)  # install() was not called: rospy's way
    if not isinstance(duration, genpy.Duration):
        duration = genpy.Duration.from_sec(duration)
    initial = rospy.rostime.get_rostime()
    while initial == genpy.Time(0) and not rospy.core.is_shutdown():  # no clock yet (as rospy)
        with cond:
            cond.wait(0.3)
        initial = rospy.rostime.get_rostime()
    deadline = initial + duration
    event = threading.Event()
    registered = False  # the deadline is in the condition's heap (once, however long the clock stalls)
    while not rospy.core.is_shutdown():
        now = rospy.rostime.get_rostime()
        if now < initial or now >= deadline:
            break
        if not registered:
            with cond:
                cond.wake_at(deadline, event)
            registered = True
        if event.wait(_SHUTDOWN_POLL):
            event.clear()
            registered = False  # its entry was taken: the deadline came, or time moved back
    now = rospy.rostime.get_rostime()
    if now < initial:
        raise rospy.exceptions.ROSTimeMovedBackwardsException((initial - now).to_sec())
    if rospy.core.is_shutdown():
        raise rospy.exceptions.ROSInterruptException('ROS shutdown request')


_installed = False


def install():
    """Puts the deadline condition and sleep() in place in this process (idempotent). Call it
    before rospy.init_node; sleeps already waiting keep rospy's way until they return."""
    global _installed
    if _installed:
        return
    cond = DeadlineCondition()
    rospy.rostime._rostime_cond = cond
    rospy.timer.sleep = sleep  # rospy.Rate and rospy.Timer sleep through it
    rospy.sleep = sleep
    rospy.core.add_shutdown_hook(lambda reason: cond.wake_everyone())  # once is_shutdown() is true
    _installed = True
