"""Injects a fault schedule into a running simulated match (scripts/run_match.py --faults).

A schedule is a list of faults, each {at: [s of match time], kind, target, duration [s],
magnitude}; robot_tools.chaos.faults draws them and says what each kind means. Three ways in:
- bus and world faults go to the simulator's /sim/inject_fault at once, with their simulated
  start time: the simulator starts and clears them on its own clock, exactly on time;
- `kidnap`: our robot moved `magnitude` metres toward the table's centre (/sim/teleport);
- process faults: `kill` (SIGKILL; roslaunch respawns the node), `stall` (SIGSTOP for
  `duration` wall seconds, then SIGCONT) of the node named by target, found by its pid over
  XML-RPC (robot_core/node_probe.py). Their end is when the node answers again.

Every fault's actual start and end (simulated time) is written to the log file as YAML, for the
invariants (robot_tools.chaos.invariants). A process fault also gets `factor`, the simulated
seconds per wall second while it lasted: what follows a restart (its publishers found by the
recorder again) takes wall time, and the invariants allow it in wall time.
"""
import math
import os
import signal
import threading
import time

import yaml

PROCESS_KINDS = ('kill', 'stall')
RESPAWN_WAIT = 30.0  # [s, wall] a killed node must answer again within this


class FaultInjector(object):
    def __init__(self, faults, log_path, match_start):
        """`match_start`: the simulated time of the start signal."""
        import rospy
        self._rospy = rospy
        self.faults = sorted((dict(f) for f in faults), key=lambda f: f['at'])
        self.log_path = log_path
        self.t0 = match_start
        self.done = []
        self._lock = threading.Lock()
        self._threads = []

    def start(self):
        from robot_sim.srv import InjectFault
        rospy = self._rospy
        rospy.wait_for_service('/sim/inject_fault', timeout=10)
        inject = rospy.ServiceProxy('/sim/inject_fault', InjectFault)
        for f in self.faults:
            if f['kind'] in PROCESS_KINDS or f['kind'] == 'kidnap':
                t = threading.Thread(target=self._at_time, args=(f,), daemon=True)
                t.start()
                self._threads.append(t)
                continue
            start = self.t0 + f['at']
            r = inject(kind=f['kind'], target=str(f.get('target', '')), start=start,
                       duration=float(f.get('duration', 0.0)), magnitude=float(f.get('magnitude', 0.0)))
            self._record(f, start, start + float(f.get('duration', 0.0)), 'injected' if r.ok else 'REFUSED: ' + r.message)

    def wait(self, timeout):
        deadline = time.monotonic() + timeout
        for t in self._threads:
            t.join(max(0.0, deadline - time.monotonic()))
        self._write()

    def _record(self, fault, start, end, outcome, wall=None):
        """`wall`: the fault's length in wall seconds, when it is a process's (gives `factor`)."""
        entry = dict(fault, start=round(start, 3), end=round(end, 3), outcome=outcome)
        if wall is not None:
            entry['factor'] = round(max(1.0, (end - start) / wall), 2) if wall > 0.05 else 1.0
        with self._lock:
            self.done.append(entry)
            self._write()

    def _write(self):
        with open(self.log_path, 'w') as f:
            yaml.safe_dump(sorted(self.done, key=lambda d: d['start']), f, default_flow_style=None)

    def _sleep_until(self, t):
        rospy = self._rospy
        while not rospy.is_shutdown() and rospy.get_time() < t:
            time.sleep(0.002)

    def _at_time(self, f):
        try:
            self._sleep_until(self.t0 + f['at'])
            if f['kind'] == 'kidnap':
                start = self._rospy.get_time()
                why = kidnap(float(f.get('magnitude') or 0.3))
                self._record(f, start, start, why)
            else:
                self._process_fault(f)
        except Exception as e:  # a fault that could not be injected is said, never silently lost
            self._record(f, self._rospy.get_time(), self._rospy.get_time(), 'FAILED: %s' % e)

    def _process_fault(self, f):
        import rosgraph
        from robot_core.node_probe import probe
        rospy = self._rospy
        master = rosgraph.Master('/run_match_faults')
        node = f['target']
        pid, why = probe(master, node, 1.0, '/run_match_faults')
        if pid is None:
            return self._record(f, rospy.get_time(), rospy.get_time(), 'FAILED: %s %s' % (node, why))
        start, wall_start = rospy.get_time(), time.monotonic()
        if f['kind'] == 'kill':
            os.kill(pid, signal.SIGKILL)
            # Its end: the respawned node answers (a new pid).
            deadline = time.monotonic() + RESPAWN_WAIT
            while time.monotonic() < deadline:
                new, _ = probe(master, node, 0.2, '/run_match_faults')
                if new is not None and new != pid:
                    return self._record(f, start, rospy.get_time(), 'killed pid %d, back as pid %d' % (pid, new),
                                        time.monotonic() - wall_start)
                time.sleep(0.05)
            return self._record(f, start, rospy.get_time(), 'killed pid %d, NOT back within %.0f s' % (pid, RESPAWN_WAIT),
                                time.monotonic() - wall_start)
        os.kill(pid, signal.SIGSTOP)
        time.sleep(float(f.get('duration', 0.5)))
        os.kill(pid, signal.SIGCONT)
        self._record(f, start, rospy.get_time(), 'stopped pid %d for %.2f s (wall)' % (pid, float(f.get('duration', 0.5))),
                     time.monotonic() - wall_start)


def kidnap(distance):
    """Our robot moved `distance` metres toward the table's centre, heading kept."""
    import rospy
    from geometry_msgs.msg import Pose2D
    from nav_msgs.msg import Odometry
    from robot_core.geometry import yaw_of
    from robot_core.params import REQUIRED, Params
    from robot_sim.srv import Teleport
    truth = rospy.wait_for_message('/sim/ground_truth', Odometry, 5.0)
    p = truth.pose.pose
    x, y = p.position.x, p.position.y
    theta = yaw_of(p.orientation)
    table = Params.from_server('/table')
    length = table.value('length', REQUIRED, float, meaning='[m] the table along x: its centre is the kidnap\'s aim')
    width = table.value('width', REQUIRED, float, meaning='[m] the table along y')
    dx, dy = length / 2.0 - x, width / 2.0 - y
    d = math.hypot(dx, dy) or 1.0
    r = rospy.ServiceProxy('/sim/teleport', Teleport)(pose=Pose2D(x + distance * dx / d, y + distance * dy / d, theta))
    return ('kidnapped %.2f m from (%.2f, %.2f)' % (distance, x, y)) if r.ok else 'REFUSED: ' + r.message
