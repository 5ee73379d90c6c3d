"""Who is the robot on the network, for the Python nodes: the twin of robot_core/command_gate.h.

The robot's network: 127.0.0.0/8, this computer's own addresses, and the config's
computer/network (address, robot_hosts, allow: addresses or CIDR networks; allow is the team's
laptop; read by robot_core/network_settings.py). A node is "foreign" when the host of its
XML-RPC URI (as the master has it) is outside.

  net = RobotNetwork.from_param_server()
  net.foreign(master, '/some_node') -> (True/False, '10.1.2.3')
  gate = CommandGate(net, match_running=lambda: ...)
  if not gate.accept(caller, '/brain/switch_strategy'): refuse
"""
import ipaddress
import socket
import subprocess
import threading
import time
from urllib.parse import urlparse

from robot_core.network_settings import read_network
from robot_core.params import Params

LOOKUP_TTL = 10.0  # [s] a node's host is asked again after this long


def local_addresses():
    """This computer's IPv4 addresses (`ip -4 -o addr`)."""
    try:
        out = subprocess.run(['ip', '-4', '-o', 'addr', 'show'], stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, universal_newlines=True, timeout=5).stdout
    except (OSError, subprocess.TimeoutExpired):
        return []
    return [line.split()[3].split('/')[0] for line in out.splitlines() if len(line.split()) > 3]


class RobotNetwork(object):
    def __init__(self, robot=(), allow=(), local=None):
        """robot: the robot's addresses or networks; allow: the allow-list (strings). ValueError
        names a bad one. local: this computer's addresses (default: asked of `ip`)."""
        def nets(items):
            out = []
            for t in items:
                try:
                    out.append(ipaddress.ip_network(str(t), strict=False))
                except ValueError:
                    raise ValueError('computer/network: %r is no IPv4 address or network' % (t,))
            return out
        self.robot = [ipaddress.ip_network('127.0.0.0/8')] + nets(robot) + nets(
            local_addresses() if local is None else local)
        self.allow = nets(allow)
        self._hosts = {}
        self._lock = threading.Lock()

    @classmethod
    def from_param_server(cls):
        """From /computer/network (robot_core/network_settings.py); ParameterError (a ValueError)
        names a bad value."""
        return cls.from_params(Params.from_server('/computer').block('network'))

    @classmethod
    def from_params(cls, network, local=None):
        """From `network`, a Params over computer/network (read_network's rules)."""
        settings = read_network(network)
        return cls([settings['address']] + settings['robot_hosts'], settings['allow'], local)

    @staticmethod
    def _within(address, nets):
        try:
            a = ipaddress.ip_address(address)
        except ValueError:
            return False
        return any(a in n for n in nets)

    def is_robot(self, address):
        return self._within(address, self.robot)

    def trusted(self, address):
        """The robot or an allowed laptop."""
        return self._within(address, self.robot + self.allow)

    def host_of(self, master, node):
        """The IPv4 address of `node`'s URI (cached), or a reason it has none."""
        with self._lock:
            cached = self._hosts.get(node)
            if cached and time.monotonic() - cached[1] < LOOKUP_TTL:
                return cached[0]
        try:
            host = urlparse(master.lookupNode(node)).hostname or ''
            address = socket.gethostbyname(host) if host else 'unknown to the master'
        except Exception as e:  # rosgraph.MasterError (no such node), socket.gaierror
            address = 'unknown to the master' if 'unknown node' in str(e).lower() or 'lookupNode' in str(e) \
                else 'unresolved (%s)' % e
        with self._lock:
            self._hosts[node] = (address, time.monotonic())
        return address

    def foreign(self, master, node):
        """(is_foreign, address) of `node`."""
        address = self.host_of(master, node)
        return not self.trusted(address), address


class CommandGate(object):
    """Commands from a foreign node are obeyed outside a match and ignored during one; both
    counted per sender for /diagnostics (statuses())."""

    def __init__(self, network, master, match_running):
        self.network, self.master, self.match_running = network, master, match_running
        self.senders = {}  # node -> {'host', 'obeyed', 'refused', 'last'}
        self._lock = threading.Lock()

    def accept(self, caller, what):
        foreign, address = self.network.foreign(self.master, caller)
        if not foreign:
            return True
        running = self.match_running()
        with self._lock:
            s = self.senders.setdefault(caller, {'host': address, 'obeyed': 0, 'refused': 0, 'last': ''})
            s['host'], s['last'] = address, what
            s['refused' if running else 'obeyed'] += 1
        return not running

    def statuses(self, node_name):
        """DiagnosticStatus per foreign sender seen: ERROR once one was ignored, else WARN."""
        from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
        out = []
        with self._lock:
            for caller, s in sorted(self.senders.items()):
                st = DiagnosticStatus(name='command gate %s: %s' % (node_name, caller), hardware_id=s['host'])
                st.level = DiagnosticStatus.ERROR if s['refused'] else DiagnosticStatus.WARN
                st.message = ('commands from %s at %s, outside the robot\'s network: %d ignored during a match, '
                              '%d obeyed outside a match (last: %s)' % (caller, s['host'], s['refused'], s['obeyed'],
                                                                         s['last']))
                st.values = [KeyValue('ignored', str(s['refused'])), KeyValue('obeyed', str(s['obeyed']))]
                out.append(st)
        return out
