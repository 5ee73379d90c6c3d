"""What make install-robot will set up for a robot, computed from config/ROBOT.yaml alone:
the validated `computer:` section (CAN bitrates, USB devices, network, real-time priority) and
this machine's ephemeral port range. Reads, never changes the host; every refusal is a
ConfigError with one line."""
import os
import re

import yaml
from robot_core.network_settings import read_network
from robot_core.params import ParameterError, Params

from robot_tools.paths import ROOT as REPO

PORT_RANGE_FILE = '/proc/sys/net/ipv4/ip_local_port_range'
DEFAULT_PORT_RANGE = (32768, 60999)   # Linux's default ip_local_port_range
DEFAULT_NETWORK = read_network(Params({}, '/computer/network'))   # the reader's defaults
IFACE_RE = re.compile(r'^[A-Za-z0-9_.-]{1,15}$')   # a Linux interface name (IFNAMSIZ - 1)
USB_ID_RE = re.compile(r'^[0-9a-fA-F]{4}$')


class ConfigError(Exception):
    pass


# ---- configuration ----

def load_config(robot, repo=REPO):
    path = os.path.join(repo, 'config', robot + '.yaml')
    if not os.path.isfile(path):
        raise ConfigError('no robot %r: %s does not exist' % (robot, path))
    with open(path) as f:
        return yaml.safe_load(f) or {}


def can_boards(config):
    """{board: interface} of the hcl blocks on a socketcan://IFACE bus."""
    boards = {}
    for name, block in sorted((config.get('hcl') or {}).items()):
        if isinstance(block, dict) and str(block.get('bus', '')).startswith('socketcan://'):
            boards[name] = block['bus'][len('socketcan://'):]
    return boards


def plan(robot, config):
    """The validated `computer:` section: {'can': {iface: bitrate}, 'devices': {board: {...,
    'path': '/dev/robot/x', 'link': 'robot/x'}}}. Raises ConfigError with one line."""
    src = 'config/%s.yaml' % robot
    computer = config.get('computer') or {}
    if not isinstance(computer, dict):
        raise ConfigError('%s: computer: must be a mapping' % src)
    can = {}
    for iface, spec in sorted((computer.get('can') or {}).items()):
        bitrate = spec.get('bitrate') if isinstance(spec, dict) else None
        if not IFACE_RE.match(str(iface)):
            raise ConfigError('%s: computer/can/%s: not an interface name' % (src, iface))
        if not isinstance(bitrate, int) or isinstance(bitrate, bool) or bitrate <= 0:
            raise ConfigError('%s: computer/can/%s/bitrate: %r is not a bitrate in bit/s' % (src, iface, bitrate))
        can[str(iface)] = bitrate
    for board, iface in sorted(can_boards(config).items()):
        if iface not in can:
            raise ConfigError('%s: hcl/%s/bus is socketcan://%s but computer/can has no bitrate for %s'
                              % (src, board, iface, iface))
    hcl = config.get('hcl') or {}
    devices = {}
    for board, spec in sorted((computer.get('devices') or {}).items()):
        where = '%s: computer/devices/%s' % (src, board)
        block = hcl.get(board)
        if not isinstance(block, dict) or 'type' not in block:
            raise ConfigError('%s: there is no board block hcl/%s' % (where, board))
        key = 'port' if 'port' in block else 'device'
        path = str(block.get(key, ''))
        if not path.startswith('/dev/') or path.endswith('/') or len(path) <= len('/dev/'):
            raise ConfigError('%s: hcl/%s/%s is %r, not a path under /dev/' % (where, board, key, path or None))
        if not isinstance(spec, dict):
            raise ConfigError('%s: must be {subsystem, vendor, product}' % where)
        for field in ('subsystem', 'vendor', 'product'):
            if not spec.get(field):
                raise ConfigError('%s: %s missing' % (where, field))
        for field in ('vendor', 'product'):
            if not USB_ID_RE.match(str(spec[field])):
                raise ConfigError('%s/%s: %r is not a 4-digit hex USB id' % (where, field, spec[field]))
        devices[board] = dict(spec, path=path, link=path[len('/dev/'):], key=key)
    return {'can': can, 'devices': devices, 'network': network_plan(src, computer.get('network')),
            'rtprio': realtime_priority(src, config)}


def realtime_priority(src, config):
    """The highest SCHED_FIFO priority the robot's processes ask for (hcl/ and hal/
    realtime_priority; 0: none): the service's LimitRTPRIO."""
    highest = 0
    for layer in ('hcl', 'hal'):
        value = (config.get(layer) or {}).get('realtime_priority', 0)
        if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= 99:
            raise ConfigError('%s: %s/realtime_priority: %r is not a priority 0..99' % (src, layer, value))
        highest = max(highest, value)
    return highest


def network_plan(src, network):
    """computer/network validated, with its defaults (loopback, 11311, no other hosts): {'address':
    '127.0.0.1', 'master_port': 11311, 'robot_hosts': [...], 'allow': [...]} (lists of str), as
    the nodes read it (robot_core/network_settings.py)."""
    try:
        return read_network(Params({'network': network}, '/computer').block('network'))
    except ParameterError as e:
        raise ConfigError('%s: %s' % (src, str(e).replace('parameter /', '', 1)))


def read_port_range(path=PORT_RANGE_FILE):
    """(low, high): the ephemeral ports this machine gives sockets bound to port 0, where roscpp's
    and rospy's XML-RPC and TCPROS/UDPROS servers listen (net.ipv4.ip_local_port_range). Linux's
    default (32768, 60999) when the file is not there."""
    try:
        with open(path) as f:
            low, high = (int(v) for v in f.read().split())
    except (IOError, OSError):
        return DEFAULT_PORT_RANGE
    except ValueError:
        raise ConfigError('%s: not two port numbers' % path)
    if not 1 <= low <= high <= 65535:
        raise ConfigError('%s: %d %d is not a port range' % (path, low, high))
    return low, high
