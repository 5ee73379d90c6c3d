"""The one clock of the brain: state timeouts, trigger debounces and hold-offs, waits, message
ages and the action slave's timing all read `now()`.

- On the robot (the default, and in unit tests): the monotonic clock. A wall clock stepped by
  NTP cannot shorten a timeout.
- In simulation the brain node calls `use_ros_time()` (under use_sim_time): ROS time, i.e. the
  simulator's /clock, so a hold-off of 1 s is one simulated second at any real-time factor.
  Nothing wakes a thread when /clock moves, so blocking waits are cut into `POLL` slices of
  wall time (`wall_slice()`) and look at the clock again; a stalled /clock holds every timeout.
"""
import time

#: [s, wall] the longest a waiter blocks before it looks at a simulated clock again
POLL = 0.005

_now = time.monotonic
_simulated = False


def now():
    """Seconds on the brain's clock (only differences mean something)."""
    return _now()


def simulated():
    return _simulated


def use_ros_time():
    """Follow ROS time (/clock under use_sim_time). Called once by the brain node at start."""
    import rospy
    use(rospy.get_time, simulated=True)


def use(clock, simulated=True):
    """Follow `clock` (a function returning seconds); tests use a clock of their own."""
    global _now, _simulated
    _now, _simulated = clock, simulated


def use_monotonic():
    use(time.monotonic, simulated=False)


def wall_slice(left):
    """How long [s, wall] to block when `left` seconds remain on this clock: all of it on the
    monotonic clock, at most POLL on a simulated one (it may run faster than the wall)."""
    left = max(0.0, left)
    return min(left, POLL) if _simulated else left


def sleep(seconds):
    """Sleep `seconds` on this clock."""
    end = now() + seconds
    while True:
        left = end - now()
        if left <= 0:
            return
        time.sleep(wall_slice(left))
