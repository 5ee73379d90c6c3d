"""Shared helpers of the Python rostests: bounded waits, topic recorders (every message, or the
newest one), percentiles, device diagnostics, and the effector switch with its service
connections opened in advance (so a measured deactivation latency starts when the request is
sent, not at the master lookup of the service), real time for a test's wall-clock case in a
simulation run as fast as the machine goes, and a launch file started and stopped as a user does."""
import contextlib
import math
import os
import signal
import subprocess
import threading
import time

import rospy
from robot_core.geometry import yaw_of  # noqa: F401 (also for the tests that import it from here)
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_srvs.srv import Trigger


def wait_for(pred, timeout, step=0.01):
    """Poll `pred` until it returns something true or `timeout` [s] passes; its last value."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        v = pred()
        if v:
            return v
        time.sleep(step)
    return pred()


class Recorder(object):
    """Keeps (receive time, message) of a topic; times are time.monotonic()."""

    def __init__(self, topic, msg_type, queue_size=500):
        self.lock = threading.Lock()
        self.items = []
        self.sub = rospy.Subscriber(topic, msg_type, self._cb, queue_size=queue_size, tcp_nodelay=True)

    def _cb(self, msg):
        with self.lock:
            self.items.append((time.monotonic(), msg))

    def connected(self, timeout=10.0):
        """True once a publisher of the topic is connected: an event published after this
        is not lost to a subscription still being set up."""
        return bool(wait_for(lambda: self.sub.get_num_connections() > 0, timeout))

    def since(self, t0=0.0):
        """(time, message) of those received at or after t0."""
        with self.lock:
            return [(t, m) for t, m in self.items if t >= t0]

    def messages(self, t0=0.0):
        """The messages received at or after t0."""
        with self.lock:
            return [m for t, m in self.items if t >= t0]

    def last(self):
        with self.lock:
            return self.items[-1][1] if self.items else None

    def wait_for(self, pred, timeout):
        """The newest message once it satisfies pred within timeout [s], else None."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.last()
            if m is not None and pred(m):
                return m
            time.sleep(0.02)
        return None


class Latest(object):
    """The newest message of a topic; with keep=True also (receive time, message) of every one
    in `items` (times are time.monotonic())."""

    def __init__(self, topic, msg_type, keep=False, queue_size=100):
        self.lock = threading.Lock()
        self.msg = None
        self.items = [] if keep else None
        self.sub = rospy.Subscriber(topic, msg_type, self._cb, queue_size=queue_size, tcp_nodelay=True)

    def _cb(self, m):
        with self.lock:
            self.msg = m
            if self.items is not None:
                self.items.append((time.monotonic(), m))

    def get(self):
        """The newest message now, or None."""
        with self.lock:
            return self.msg

    def wait(self, timeout=10.0, pred=None):
        """The newest message once there is one (satisfying pred if given) within timeout [s],
        else None."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.get()
            if m is not None and (pred is None or pred(m)):
                return m
            time.sleep(0.02)
        return None

    def since(self, t0=0.0):
        """The kept messages received at or after t0 (keep=True)."""
        with self.lock:
            return [m for t, m in self.items if t >= t0]


def percentile(values, q):
    """The q-th percentile (0..100) of values: the sorted value nearest the rank
    q/100 * (n - 1), no interpolation; NaN if there are none."""
    s = sorted(values)
    return s[min(len(s) - 1, int(round(q / 100.0 * (len(s) - 1))))] if s else float('nan')


class DeviceDiagnostics(object):
    """The newest status of each device or board (by a part of its name) on /diagnostics, or on
    /diagnostics_agg with topic='/diagnostics_agg'."""

    def __init__(self, topic='/diagnostics'):
        self.lock = threading.Lock()
        self.items = []
        self.sub = rospy.Subscriber(topic, DiagnosticArray, self._cb, queue_size=500)

    def _cb(self, arr):
        now = time.monotonic()
        with self.lock:
            for s in arr.status:
                self.items.append((now, s))

    def status(self, name_part, since=0.0):
        """The newest status whose name contains name_part (e.g. 'hal/drive': names are
        'hal/drive: device'), received after `since`."""
        with self.lock:
            for t, s in reversed(self.items):
                if t >= since and name_part in s.name:
                    return s
        return None

    def wait_for(self, name_part, pred, timeout, since=None):
        """The first newest status of name_part, received after `since`, satisfying pred."""
        since = time.monotonic() if since is None else since

        def check():
            s = self.status(name_part, since)
            return s if s is not None and pred(s) else None
        return wait_for(check, timeout, step=0.02)


def value(status, key):
    for kv in status.values:
        if kv.key == key:
            return kv.value
    return None


def is_ok(status):
    return status.level == DiagnosticStatus.OK


def is_active(status):
    return value(status, 'active') in ('True', 'true', '1')


class EffectorSwitch(object):
    """/effectors/deactivate and /effectors/activate over persistent connections, opened by one
    deactivate/activate cycle at construction (call it before the effectors are in use)."""

    def __init__(self, timeout=20.0):
        rospy.wait_for_service('/effectors/deactivate', timeout)
        rospy.wait_for_service('/effectors/activate', timeout)
        self._deactivate = rospy.ServiceProxy('/effectors/deactivate', Trigger, persistent=True)
        self._activate = rospy.ServiceProxy('/effectors/activate', Trigger, persistent=True)
        self.deactivate()
        self.activate()

    def deactivate(self):
        return self._deactivate()

    def activate(self):
        return self._activate()


@contextlib.contextmanager
def real_time(simulator='/sim'):
    """Inside the block the simulation runs at real time (factor 1), then goes back to the
    factor it was launched with (its ~real_time_factor). For the cases that bound a latency in
    wall milliseconds in a test otherwise run as fast as the machine goes: at a higher factor
    the processing a latency measures takes the same wall time but more simulated time, and the
    machine is kept 80-90 % busy. A simulation launched at real time is left alone."""
    launched = float(rospy.get_param(simulator + '/real_time_factor', 1.0))
    if launched == 1.0:
        yield
        return
    from robot_sim.srv import SetRealTimeFactor
    service = simulator + '/set_real_time_factor'
    rospy.wait_for_service(service, 10.0)
    set_factor = rospy.ServiceProxy(service, SetRealTimeFactor)
    r = set_factor(1.0)
    assert r.ok, r.message
    time.sleep(1.0)  # the machine settles from the fast pace before anything is timed
    try:
        yield
    finally:
        set_factor(launched)


def roslaunch(*args, log):
    """`roslaunch --wait ARGS` in a session of its own (stop() signals the whole group), its
    output into the open file `log`."""
    return subprocess.Popen(['roslaunch', '--wait'] + list(args), stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)


def stop(proc, timeout=30.0):
    """Ctrl-C to a roslaunch() as a user stops it; SIGKILL to what is left after `timeout` [s]."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
