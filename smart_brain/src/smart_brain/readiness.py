"""Readiness: is the robot ready for a match? Ready means every required product node runs and
every board and device is OK on /diagnostics_agg (Debian's diagnostic_aggregator, one item per
board under /Boards and per device under /Devices, config/diagnostics_aggregator.yaml).

Every board and device means every one the HCL and the HAL loaded (each host's `status_names`
parameter, robot_core/component_host.h), so one that has not reported yet holds the start too:
"/hal: hal/odometry: device is missing: no status on /diagnostics_agg yet".

Otherwise `check()` names what is not, e.g. "/hcl died: parameter /hcl/motor_board/rate = -100:
must be > 0" (a node's last FATAL or ERROR line on /rosout_agg is its last word) or
"/Boards/motor_board: board is STALE: board not answering for 0.52 s".

An optional board (`required: false` in its config block, published as the `required` value of
its status) is reported but does not hold the start.

Parameters (the brain's, config/<robot>.yaml `brain: ready:`):
  ~ready/nodes     product nodes that must run (default [/hcl, /hal])
  ~ready/optional  status names (substrings) whose level does not hold the start (default [])
"""
import threading

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rosgraph_msgs.msg import Log
from robot_core.node_probe import probe

LEVELS = {DiagnosticStatus.OK: 'OK', DiagnosticStatus.WARN: 'WARN', DiagnosticStatus.ERROR: 'ERROR',
          DiagnosticStatus.STALE: 'STALE'}
GROUPS = ('/Boards/', '/Devices/')


def node_alive(master, name, timeout=0.5):
    """True if `name` is registered with the master and answers within `timeout` wall seconds."""
    return probe(master, name, timeout, '/brain')[0] is not None


def is_required(status):
    """False when the status says its component is optional (its `required` value is false)."""
    return not any(kv.key == 'required' and kv.value.strip().lower() in ('false', 'no') for kv in status.values)


def missing_items(statuses, expected, optional=()):
    """The expected status names ("hal/odometry: device", as their host publishes them) with no
    leaf on /diagnostics_agg. The aggregator files "hal/odometry: device" as "/Devices/odometry:
    device": the leaf ends with the name less its host's prefix (the kind keeps a board and a
    device of one name apart)."""
    leaves = list(statuses)
    missing = []
    for name in expected:
        tail = '/' + name.split('/', 1)[-1]
        if any(o in name for o in optional) or any(leaf.endswith(tail) for leaf in leaves):
            continue
        missing.append(name)
    return missing


def diagnostics_problems(statuses, optional=(), expected=()):
    """The boards' and devices' items that are not OK: ['/Boards/x: board is STALE: why', ...],
    and those expected but missing. `statuses`: name -> (level, message, required)."""
    problems = ['%s is missing: no status on /diagnostics_agg yet' % name
                for name in missing_items(statuses, expected, optional)]
    for name in sorted(statuses):
        level, message, required = statuses[name]
        if level == DiagnosticStatus.OK or not required or any(o in name for o in optional):
            continue
        if level == DiagnosticStatus.STALE:  # the aggregator's: nothing new, its last words are old news
            problems.append('%s is STALE: no fresh report%s' % (name, ' (last said: %s)' % message if message else ''))
        else:
            problems.append('%s is %s: %s' % (name, LEVELS.get(level, level), message))
    return problems


class Readiness(object):
    def __init__(self, nodes=('/hcl', '/hal'), optional=()):
        self.nodes = list(nodes)
        self.optional = list(optional)
        self._lock = threading.Lock()
        self._statuses = None     # leaf item name -> (level, message), from /diagnostics_agg
        self._last_words = {}     # node -> its last FATAL/ERROR line
        self._seen_alive = set()
        self._master = rosgraph.Master(rospy.get_name())
        self._agg_sub = rospy.Subscriber('/diagnostics_agg', DiagnosticArray, self._on_agg, queue_size=2)
        self._log_sub = rospy.Subscriber('/rosout_agg', Log, self._on_log, queue_size=50)

    def _on_agg(self, msg):
        leaves = {}
        for s in msg.status:
            if s.name.startswith(GROUPS) and s.name.count('/') == 2:
                leaves[s.name] = (s.level, s.message, is_required(s))
        with self._lock:
            self._statuses = leaves

    def _on_log(self, msg):
        if msg.level >= Log.ERROR and msg.name in self.nodes:
            with self._lock:
                self._last_words[msg.name] = msg.msg.splitlines()[0] if msg.msg else ''

    def expected_status_names(self):
        """What the running hosts said they publish (their `status_names` parameter)."""
        names = []
        for node in self.nodes:
            try:
                # a live value a (re)starting host writes: read at each check, not once at start
                value = rospy.get_param(node.rstrip('/') + '/status_names', [])
            except (KeyError, OSError):
                value = []
            names += [n for n in value if isinstance(n, str)] if isinstance(value, list) else []
        return names

    def check(self):
        """(ready, text, what): text is 'ready' or 'not ready: <what, why>; <what, why>', `what`
        the names of what is not ready (it changes when something new fails or recovers, not
        when a reason's figures do)."""
        problems = []
        for node in self.nodes:
            if node_alive(self._master, node):
                self._seen_alive.add(node)
                continue
            with self._lock:
                words = self._last_words.get(node)
            if words:
                problems.append('%s died: %s' % (node, words))
            elif node in self._seen_alive:
                problems.append('%s died' % node)
            else:
                problems.append('%s is not running' % node)
        with self._lock:
            statuses = self._statuses
        expected = self.expected_status_names()
        if statuses is None:
            problems.append('nothing on /diagnostics_agg yet (is diagnostic_aggregator running?)')
        elif not statuses:
            problems.append('no board or device reports on /diagnostics_agg')
        else:
            problems += diagnostics_problems(statuses, self.optional, expected)
        if not problems:
            return True, 'ready', ()
        what = tuple(p.split(' is ')[0].split(' died')[0] for p in problems)
        return False, 'not ready: ' + '; '.join(problems), what
