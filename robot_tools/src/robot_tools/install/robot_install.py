#!/usr/bin/python3
"""Sets the robot's own computer up for one robot, and undoes it (make install-robot /
make uninstall-robot; docs/real-robot.md "The robot's computer").

    robot_install.py install ROBOT [--root DIR] [--dry-run] [--start]
    robot_install.py uninstall ROBOT [--root DIR] [--dry-run]
    robot_install.py allow|deny ROBOT ADDR   (the running firewall's allow-list, until reboot)
    robot_install.py status ROBOT            (the allow-list and the ros_dropped counter)

What it installs comes from config/ROBOT.yaml, section `computer:` (none: only the service):
  * per CAN interface of `computer: can:`, a oneshot unit robot-can-IFACE.service bound to the
    interface's device unit, enabled for it (the interface comes up at its bitrate at boot and
    whenever the adapter appears), started now when the interface exists;
  * /etc/udev/rules.d/99-robot-ROBOT.rules: per `computer: devices:` entry, a rule giving the
    USB device the stable name its board block uses (hcl/<board>/port or device, /dev/robot/x);
  * /etc/robot/ROBOT.nft and robot-firewall-ROBOT.service: an nftables table of its own,
    inet robot_ROBOT, accepting the ROS ports (master, XML-RPC and TCPROS/UDPROS servers on the
    ephemeral ports) only from loopback, the robot's own addresses and `computer: network:
    allow:`; the rest to them dropped and counted (ros_dropped). Enabled, loaded at install;
  * robot-ROBOT.service: `roslaunch launch/ROBOT.launch sim:=false` at boot with ROS_IP and
    ROS_MASTER_URI on `computer: network: address:` (default 127.0.0.1), after the firewall,
    enabled, started only with --start;
  * /var/lib/robot/ROBOT/: the service's home (ROS_HOME, ROS_LOG_DIR) and installed.txt, the
    manifest uninstall removes (files, symlinks, then the directories it created, when empty).
With --root DIR everything goes under DIR and nothing on this machine is called (systemctl,
udevadm, ip, nft); --dry-run only prints what it would do. One function per installed thing: each
returns the Items (files, enable symlinks, directories) it puts in place.
"""
import argparse
import ipaddress
import os
import re
import shlex
import subprocess
import sys

import yaml

from robot_tools.paths import ROOT as REPO
UNIT_DIR = '/etc/systemd/system'
RULES_DIR = '/etc/udev/rules.d'
STATE_DIR = '/var/lib/robot'
IP = '/sbin/ip'
NFT = '/usr/sbin/nft'
NFT_DIR = '/etc/robot'
PORT_RANGE_FILE = '/proc/sys/net/ipv4/ip_local_port_range'
DEFAULT_PORT_RANGE = (32768, 60999)   # Linux's default ip_local_port_range
DEFAULT_NETWORK = {'address': '127.0.0.1', 'master_port': 11311, 'robot_hosts': [], 'allow': []}
PATH = '/usr/bin:/bin:/usr/sbin:/sbin'
IFACE_RE = re.compile(r'^[A-Za-z0-9_.-]{1,15}$')   # a Linux interface name (IFNAMSIZ - 1)
USB_ID_RE = re.compile(r'^[0-9a-fA-F]{4}$')


class ConfigError(Exception):
    pass


class Item(object):
    """One thing on the disk: a file (content), a symlink (target) or a directory."""

    def __init__(self, path, content=None, link=None, directory=False, mode=0o644):
        self.path, self.content, self.link, self.directory, self.mode = path, content, link, directory, mode

    def kind(self):
        return 'dir' if self.directory else 'link' if self.link is not None else 'file'


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


def ipv4_network(text):
    """An IPv4 address or CIDR network (no host bits set) as an IPv4Network; ValueError else."""
    if isinstance(text, bool) or not isinstance(text, (str, int)) or ':' in str(text):
        raise ValueError(text)
    return ipaddress.IPv4Network(str(text).strip(), strict=True)


def network_plan(src, network):
    """computer/network validated, with its defaults (loopback, 11311, no other hosts): {'address':
    '127.0.0.1', 'master_port': 11311, 'robot_hosts': [...], 'allow': [...]} (lists of str)."""
    if network is None:
        network = {}
    if not isinstance(network, dict):
        raise ConfigError('%s: computer/network: must be a mapping {address, master_port, robot_hosts, allow}' % src)
    unknown = sorted(set(map(str, network)) - set(DEFAULT_NETWORK))
    if unknown:
        raise ConfigError('%s: computer/network/%s: unknown key (address, master_port, robot_hosts, allow)'
                          % (src, unknown[0]))
    out = dict(DEFAULT_NETWORK, **network)
    address = out['address']
    try:
        if isinstance(address, bool) or not isinstance(address, (str, int)):
            raise ValueError(address)
        ip = ipaddress.IPv4Address(str(address).strip())
    except ValueError:
        raise ConfigError('%s: computer/network/address: %r is not an IPv4 address' % (src, address))
    if ip.is_unspecified or ip.is_multicast:
        raise ConfigError('%s: computer/network/address: %s is not an address of the robot' % (src, ip))
    port = out['master_port']
    if not isinstance(port, int) or isinstance(port, bool) or not 1 <= port <= 65535:
        raise ConfigError('%s: computer/network/master_port: %r is not a port (1..65535)' % (src, port))
    lists = {}
    for key in ('robot_hosts', 'allow'):
        value = out[key]
        if value is None:
            value = []
        if not isinstance(value, list):
            raise ConfigError('%s: computer/network/%s: must be a list of IPv4 addresses or networks' % (src, key))
        lists[key] = []
        for entry in value:
            try:
                lists[key].append(str(ipv4_network(entry)))
            except ValueError:
                raise ConfigError('%s: computer/network/%s: %r is not an IPv4 address or network (a.b.c.d or '
                                  'a.b.c.0/24)' % (src, key, entry))
    return {'address': str(ip), 'master_port': port, 'robot_hosts': lists['robot_hosts'], 'allow': lists['allow']}


# ---- the installed things: one function each ----

def can_unit_name(iface):
    return 'robot-can-%s.service' % iface


def device_unit(iface):
    return 'sys-subsystem-net-devices-%s.device' % iface.replace('-', '\\x2d')


def can_unit(robot, iface, bitrate):
    """robot-can-IFACE.service: the interface down, its bitrate set, up; whenever it appears."""
    dev = device_unit(iface)
    name = can_unit_name(iface)
    text = '\n'.join([
        '# Installed by make install-robot ROBOT=%s (scripts/robot_install.py); removed by' % robot,
        '# make uninstall-robot. Bitrate from config/%s.yaml computer/can/%s.' % (robot, iface),
        '[Unit]',
        'Description=CAN interface %s at %d bit/s (robot %s)' % (iface, bitrate, robot),
        'BindsTo=%s' % dev,
        'After=%s' % dev,
        '',
        '[Service]',
        'Type=oneshot',
        'RemainAfterExit=yes',
        'ExecStart=-%s link set %s down' % (IP, iface),
        'ExecStart=%s link set %s type can bitrate %d restart-ms 100' % (IP, iface, bitrate),
        'ExecStart=%s link set %s up' % (IP, iface),
        '',
        '[Install]',
        'WantedBy=%s' % dev,
        ''])
    return [Item(os.path.join(UNIT_DIR, name), text),
            Item(os.path.join(UNIT_DIR, dev + '.wants', name), link=os.path.join(UNIT_DIR, name))]


def rules_path(robot):
    return os.path.join(RULES_DIR, '99-robot-%s.rules' % robot)


def udev_rules(robot, devices):
    """99-robot-ROBOT.rules: each configured USB device gets its board block's /dev/ name."""
    if not devices:
        return []
    lines = ['# Installed by make install-robot ROBOT=%s (scripts/robot_install.py); removed by' % robot,
             '# make uninstall-robot. From config/%s.yaml computer/devices: each USB device gets' % robot,
             '# the name its board block uses.']
    for board, d in sorted(devices.items()):
        match = ['SUBSYSTEM=="%s"' % d['subsystem']]
        if d['subsystem'] == 'input':
            match.append('KERNEL=="js*"')   # the joystick interface, not its event node
        match += ['ATTRS{idVendor}=="%s"' % str(d['vendor']).lower(),
                  'ATTRS{idProduct}=="%s"' % str(d['product']).lower()]
        if d.get('serial'):
            match.append('ATTRS{serial}=="%s"' % d['serial'])
        lines.append('# hcl/%s/%s: %s' % (board, d['key'], d['path']))
        lines.append(', '.join(match + ['SYMLINK+="%s"' % d['link']]))
    return [Item(rules_path(robot), '\n'.join(lines) + '\n')]


def service_name(robot):
    return 'robot-%s.service' % robot


def state_dir(robot):
    return os.path.join(STATE_DIR, robot)


def systemd_escape(text):
    return text.replace('%', '%%')


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


def table_name(robot):
    return 'robot_%s' % robot


def nft_path(robot):
    return os.path.join(NFT_DIR, robot + '.nft')


def firewall_unit_name(robot):
    return 'robot-firewall-%s.service' % robot


def allowed_elements(network):
    """The set `allowed`: loopback, the robot's address, its other computers and the allow-list,
    merged into non-overlapping networks (an nftables interval set refuses overlapping ones)."""
    nets = [ipaddress.IPv4Network('127.0.0.0/8'), ipaddress.IPv4Network(network.get('address') or '127.0.0.1')]
    nets += [ipv4_network(n) for n in list(network.get('robot_hosts') or []) + list(network.get('allow') or [])]
    return [str(n) if n.prefixlen < 32 else str(n.network_address) for n in ipaddress.collapse_addresses(nets)]


def firewall_rules(robot, network, port_range):
    """The nftables ruleset of the robot (the text of /etc/robot/ROBOT.nft, for `nft -f`): a table
    inet robot_ROBOT of its own, replaced whole on each load; TCP to the master port and TCP/UDP to
    the ephemeral ports (port_range = (low, high)) accepted on loopback, for established
    connections and from the set `allowed`, else dropped and counted in ros_dropped. Other ports
    untouched. network: computer/network (address, master_port, robot_hosts, allow)."""
    table = table_name(robot)
    port = int(network.get('master_port', DEFAULT_NETWORK['master_port']))
    low, high = (int(p) for p in port_range)
    ephemeral = '%d-%d' % (low, high) if low < high else '%d' % low
    ros_ports = [('tcp', str(port), 'the master (XML-RPC)'),
                 ('tcp', ephemeral, 'the nodes\' XML-RPC and TCPROS servers (ephemeral ports)'),
                 ('udp', ephemeral, 'UDPROS (ephemeral ports)')]
    lines = [
        '#!%s -f' % NFT,
        '# Installed by make install-robot ROBOT=%s (scripts/robot_install.py); loaded by' % robot,
        '# %s, removed by make uninstall-robot. From config/%s.yaml computer/network;' % (firewall_unit_name(robot), robot),
        '# ephemeral ports %d-%d from %s at install.' % (low, high, PORT_RANGE_FILE),
        '# ROS has no authentication: its ports (master %d, the nodes\' XML-RPC and TCPROS/UDPROS' % port,
        '# servers on the ephemeral ports) only from the robot itself and the set `allowed`; the',
        '# rest to them dropped and counted. For one match: make allow-laptop ROBOT=%s ADDR=...' % robot,
        '# The table is replaced whole: declared (created when missing), deleted, declared again.',
        'table inet %s' % table,
        'delete table inet %s' % table,
        '',
        'table inet %s {' % table,
        '	set allowed {',
        '		type ipv4_addr',
        '		flags interval',
        '		elements = { %s }' % ', '.join(allowed_elements(network)),
        '	}',
        '',
        '	counter ros_dropped {',
        '	}',
        '',
        '	chain input {',
        '		type filter hook input priority filter; policy accept;',
        '		iif "lo" accept',
        '		ct state established,related accept',
    ]
    for proto, ports, what in ros_ports:
        lines.append('		%s dport %s ip saddr @allowed accept comment "%s"' % (proto, ports, what.replace('"', "'")))
    for proto, ports, what in ros_ports:   # the rest, IPv6 included
        lines.append('		%s dport %s counter name "ros_dropped" drop' % (proto, ports))
    lines += ['	}', '}', '']
    return '\n'.join(lines)


def firewall_unit(robot):
    """robot-firewall-ROBOT.service: loads /etc/robot/ROBOT.nft before the network and the robot
    come up; stopping it deletes the table. Reload (nft -f again) leaves the robot running."""
    table = table_name(robot)
    text = '\n'.join([
        '# Installed by make install-robot ROBOT=%s (scripts/robot_install.py); removed by' % robot,
        '# make uninstall-robot. The rules: %s; loaded: nft list table inet %s' % (nft_path(robot), table),
        '[Unit]',
        'Description=Firewall of robot %s\'s ROS ports (nftables table inet %s)' % (robot, table),
        'Documentation=man:nft(8)',
        '# Like Debian\'s nftables.service: in place before any network interface is up.',
        'DefaultDependencies=no',
        'Wants=network-pre.target',
        'After=nftables.service',
        'Before=network-pre.target shutdown.target %s' % service_name(robot),
        'Conflicts=shutdown.target',
        '',
        '[Service]',
        'Type=oneshot',
        'RemainAfterExit=yes',
        'ExecStart=%s -f %s' % (NFT, nft_path(robot)),
        'ExecReload=%s -f %s' % (NFT, nft_path(robot)),
        'ExecStop=-%s delete table inet %s' % (NFT, table),
        '',
        '[Install]',
        'WantedBy=multi-user.target',
        ''])
    name = firewall_unit_name(robot)
    return [Item(os.path.join(UNIT_DIR, name), text),
            Item(os.path.join(UNIT_DIR, 'multi-user.target.wants', name), link=os.path.join(UNIT_DIR, name))]


def firewall(robot, network, port_range):
    """/etc/robot/ROBOT.nft and the unit that loads it."""
    return [Item(NFT_DIR, directory=True), Item(nft_path(robot), firewall_rules(robot, network, port_range))] + \
        firewall_unit(robot)


def robot_service(robot, can, repo=REPO, network=None, rtprio=0):
    """robot-ROBOT.service: the robot's launch on the real robot, at boot, restarted on failure;
    its master and nodes on the robot's address, after its firewall; allowed the real-time
    priority its loops ask for and to lock their memory (robot_core/realtime.h)."""
    network = network or DEFAULT_NETWORK
    home = state_dir(robot)
    cans = ' '.join(can_unit_name(i) for i in sorted(can))
    script = 'set +u; source %s && exec roslaunch %s sim:=false' % (
        shlex.quote(os.path.join(repo, 'devel', 'setup.bash')),
        shlex.quote(os.path.join(repo, 'launch', robot + '.launch')))
    text = '\n'.join([
        '# Installed by make install-robot ROBOT=%s (scripts/robot_install.py); removed by' % robot,
        '# make uninstall-robot. Logs: journalctl -u robot-%s; restart: systemctl restart robot-%s' % (robot, robot),
        '[Unit]',
        'Description=Robot %s: roslaunch launch/%s.launch sim:=false' % (robot, robot),
        '# No firewall, no robot: ROS has no authentication (docs/real-robot.md "Nobody outside the robot drives it")',
        'Requires=%s' % firewall_unit_name(robot),
        'Wants=network-online.target' + (' ' + cans if cans else ''),
        'After=network-online.target %s' % firewall_unit_name(robot) + (' ' + cans if cans else ''),
        '',
        '[Service]',
        'Type=simple',
        'Environment=PATH=%s' % PATH,
        'Environment=HOME=%s ROS_HOME=%s ROS_LOG_DIR=%s' % (home, os.path.join(home, 'ros'), os.path.join(home, 'log')),
        'Environment=PYTHONNOUSERSITE=1 ROS_PYTHON_VERSION=3',
        '# The master and every node on the robot\'s address (computer/network/address); rosmaster and',
        '# rospy bind only loopback when it is loopback, roscpp binds all: the firewall does the rest',
        'Environment=ROS_IP=%s ROS_MASTER_URI=http://%s:%d' % (network['address'], network['address'],
                                                              network['master_port']),
        'UnsetEnvironment=ROS_HOSTNAME',
        '# The bus and device loops in SCHED_FIFO (hcl/ and hal/realtime_priority) with their memory',
        '# locked: the right to both, also under a User= without root',
        'LimitRTPRIO=%d' % rtprio,
        'LimitMEMLOCK=infinity',
        'WorkingDirectory=%s' % home,
        'ExecStart=/bin/bash -c %s' % systemd_escape(shlex.quote(script)),
        'Restart=on-failure',
        'RestartSec=5',
        '# roslaunch stops its nodes on SIGINT (up to 15 s SIGINT, then SIGTERM); SIGKILL for what is left',
        'KillMode=mixed',
        'KillSignal=SIGINT',
        'TimeoutStopSec=30',
        'StandardOutput=journal',
        'StandardError=journal',
        'SyslogIdentifier=robot-%s' % robot,
        '',
        '[Install]',
        'WantedBy=multi-user.target',
        ''])
    return [Item(os.path.join(UNIT_DIR, service_name(robot)), text),
            Item(os.path.join(UNIT_DIR, 'multi-user.target.wants', service_name(robot)),
                 link=os.path.join(UNIT_DIR, service_name(robot)))]


def manifest_path(robot):
    return os.path.join(state_dir(robot), 'installed.txt')


def items(robot, config, repo=REPO, port_range=None):
    """Everything install puts in place, in order (the manifest is written last)."""
    p = plan(robot, config)
    port_range = port_range or read_port_range()
    home = state_dir(robot)
    out = [Item(STATE_DIR, directory=True), Item(home, directory=True),
           Item(os.path.join(home, 'ros'), directory=True), Item(os.path.join(home, 'log'), directory=True)]
    for iface, bitrate in sorted(p['can'].items()):
        out += can_unit(robot, iface, bitrate)
    out += udev_rules(robot, p['devices'])
    out += firewall(robot, p['network'], port_range)
    out += robot_service(robot, p['can'], repo, p['network'], p['rtprio'])
    return p, out


# ---- putting them in place ----

class Host(object):
    """The file system under root and the commands run on this machine (none under a staging
    root or in a dry run)."""

    def __init__(self, root='/', dry_run=False, out=sys.stdout):
        self.root = os.path.abspath(root)
        self.staging = self.root != '/'
        self.dry_run = dry_run
        self.out = out
        self.planned = set()   # directories a dry run would have created
        self.failed = []       # commands that failed

    def say(self, text):
        self.out.write(text + '\n')
        self.out.flush()

    def at(self, path):
        return os.path.join(self.root, path.lstrip('/'))

    def live(self):
        return not self.staging and not self.dry_run

    def systemd_running(self):
        return os.path.isdir('/run/systemd/system')

    def udevd_running(self):
        return subprocess.call(['udevadm', 'control', '--ping'], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL) == 0

    def run(self, cmd, check=True):
        if self.dry_run:
            self.say('would run: ' + ' '.join(cmd))
            return 0
        if self.staging:
            return 0
        rc = subprocess.call(cmd)
        if rc and check:
            self.say('FAILED (exit %d): %s' % (rc, ' '.join(cmd)))
            self.failed.append(' '.join(cmd))
        return rc


def existing_manifest(host, robot):
    path = host.at(manifest_path(robot))
    if not os.path.isfile(path):
        return None
    with open(path) as f:
        return [l.rstrip('\n') for l in f if l.strip() and not l.startswith('#')]


def missing_dirs(host, path):
    """The directories above path (path itself for a directory item) that do not exist yet, top first."""
    out = []
    while path not in ('/', '') and not os.path.isdir(host.at(path)) and path not in host.planned:
        out.insert(0, path)
        path = os.path.dirname(path)
    return out


def put(host, item):
    """Puts one item in place (replacing what was there); returns the directories it created."""
    made = missing_dirs(host, item.path if item.directory else os.path.dirname(item.path))
    if host.dry_run:
        for d in made:
            host.say('would create %s/' % d)
            host.planned.add(d)
        if not item.directory:
            host.say('would write %s%s' % (item.path, ' -> ' + item.link if item.link else ''))
            if item.content is not None:
                host.say('    ' + item.content.rstrip('\n').replace('\n', '\n    '))
        return made
    for d in made:
        os.mkdir(host.at(d), 0o755)
        host.say('created %s/' % d)
    if item.directory:
        return made
    path = host.at(item.path)
    if os.path.lexists(path):
        os.remove(path)
    if item.link is not None:
        os.symlink(item.link, path)
    else:
        tmp = path + '.tmp'
        with open(tmp, 'w') as f:
            f.write(item.content)
        os.chmod(tmp, item.mode)
        os.rename(tmp, path)
    host.say('installed %s%s' % (item.path, ' -> ' + item.link if item.link else ''))
    return made


def install(robot, host, start=False, repo=REPO):
    config = load_config(robot, repo)
    p, todo = items(robot, config, repo)
    if host.live() and not os.path.isfile(os.path.join(repo, 'devel', 'setup.bash')):
        raise ConfigError('%s/devel/setup.bash missing: build the workspace first (make build)' % repo)
    old = [l.split(' ', 1) for l in existing_manifest(host, robot) or []]
    ours = set(path for _, path in old)
    for item in todo:   # never overwrite another robot's or the system's file
        path = host.at(item.path)
        if not item.directory and os.path.lexists(path) and item.path not in ours:
            same = (item.link is not None and os.path.islink(path) and os.readlink(path) == item.link) or \
                   (item.content is not None and os.path.isfile(path) and open(path).read() == item.content)
            if not same:
                raise ConfigError('%s exists and was not installed for %s (another robot? make uninstall-robot '
                                  'ROBOT=<it> first)' % (item.path, robot))
    # Reinstall: remove what the last install put there and this one does not.
    keep = set(i.path for i in todo if not i.directory) | {manifest_path(robot)}
    stale = [(k, path) for k, path in old if k != 'dir' and path not in keep]
    for kind, path in reversed(stale):
        remove(host, kind, path)
    dirs = []   # directories this install (or the last) created: uninstall removes them when empty
    for kind, path in sorted((e for e in old if e[0] == 'dir'), key=lambda e: -len(e[1])):
        if stale and not host.dry_run:
            remove(host, kind, path, quiet=True)
        if os.path.isdir(host.at(path)):
            dirs.append(path)
    if host.staging and not host.dry_run:
        os.makedirs(host.root, exist_ok=True)
    files = []
    for item in todo:
        dirs += [d for d in put(host, item) if d not in dirs]
        if not item.directory:
            files.append('%s %s' % (item.kind(), item.path))
    lines = ['dir %s' % d for d in sorted(dirs)] + files + ['file %s' % manifest_path(robot)]
    manifest = '# make install-robot ROBOT=%s: what make uninstall-robot removes (kind path)\n' % robot
    manifest += '\n'.join(lines) + '\n'
    if host.dry_run:
        host.say('would write %s' % manifest_path(robot))
    else:
        with open(host.at(manifest_path(robot)), 'w') as f:
            f.write(manifest)
        host.say('installed %s' % manifest_path(robot))
    activate(robot, p, host, start)
    return lines


def activate(robot, p, host, start):
    """systemd and udev take the new files; CAN up now where the interface exists."""
    if host.staging:
        host.say('staging root %s: no systemctl, udevadm, ip or nft calls' % host.root)
        return
    systemd = host.dry_run or host.systemd_running()
    if systemd:
        host.run(['systemctl', 'daemon-reload'])
    else:
        host.say('systemd is not running here: units installed and enabled, none started')
    for iface in sorted(p['can']):
        if not os.path.exists('/sys/class/net/%s' % iface):
            host.say('%s does not exist yet: %s brings it up at %d bit/s when the adapter appears'
                     % (iface, can_unit_name(iface), p['can'][iface]))
        elif systemd:
            host.run(['systemctl', 'restart', can_unit_name(iface)])
    rules = nft_path(robot)
    if systemd:   # reload: new rules, the robot (Requires= it) not restarted
        host.run(['systemctl', 'reload-or-restart', firewall_unit_name(robot)])
    else:
        host.say('loading %s directly (%s starts it at boot)' % (rules, firewall_unit_name(robot)))
        host.run([NFT, '-f', rules])
    if p['devices']:
        if host.dry_run or host.udevd_running():
            host.run(['udevadm', 'control', '--reload'])
            host.run(['udevadm', 'trigger'] +
                     ['--subsystem-match=%s' % s for s in sorted(set(d['subsystem'] for d in p['devices'].values()))])
        else:
            host.say('udevd is not running here: the rules apply from the next boot')
    if start and systemd:
        if host.run(['systemctl', 'restart', service_name(robot)]) == 0 and not host.dry_run:
            host.say('started %s: journalctl -u robot-%s -f' % (service_name(robot), robot))
    elif start:
        host.say('%s enabled (starts at boot); not started: no systemd here' % service_name(robot))
    else:
        host.say('%s enabled (starts at boot); not started now (START=1 starts it)' % service_name(robot))


def remove(host, kind, path, quiet=False):
    target = host.at(path)
    if kind == 'dir':
        if os.path.isdir(target) and not os.path.islink(target):
            if os.listdir(target):
                if not quiet:
                    host.say('kept %s/: not empty (%s)' % (path, ', '.join(sorted(os.listdir(target))[:5])))
            elif host.dry_run:
                host.say('would remove %s/' % path)
            else:
                os.rmdir(target)
                host.say('removed %s/' % path)
        return
    if os.path.lexists(target):
        if host.dry_run:
            host.say('would remove %s' % path)
        else:
            os.remove(target)
            host.say('removed %s' % path)


def uninstall(robot, host, repo=REPO):
    lines = existing_manifest(host, robot)
    if lines is None:   # no manifest: what install would put there now
        host.say('no %s: removing what install would put there for config/%s.yaml' % (manifest_path(robot), robot))
        _, todo = items(robot, load_config(robot, repo), repo)
        lines = ['%s %s' % (i.kind(), i.path) for i in todo if not (i.directory and i.path == STATE_DIR)]
        lines += ['dir ' + os.path.dirname(i.path) for i in todo if os.path.dirname(i.path).endswith('.device.wants')]
    entries = [l.split(' ', 1) for l in lines]
    units = [os.path.basename(p) for k, p in entries if k == 'file' and p.endswith('.service')]
    # The robot first, then its CAN units (no ip call: the interfaces stay as they are).
    units.sort(key=lambda u: u != service_name(robot))
    live_systemd = not host.staging and (host.dry_run or host.systemd_running())
    if live_systemd:   # stopping the firewall unit deletes its table
        for unit in units:
            host.run(['systemctl', 'stop', unit], check=False)
    # Without systemd (or a table loaded by hand): nft itself.
    if not host.staging and (not host.dry_run or not host.systemd_running()) and table_loaded(robot):
        host.run([NFT, 'delete', 'table', 'inet', table_name(robot)])
    # Files and links first, in reverse; then directories, deepest first.
    for kind, path in reversed(entries):
        if kind != 'dir':
            remove(host, kind, path)
    for kind, path in sorted((e for e in entries if e[0] == 'dir'), key=lambda e: -len(e[1])):
        remove(host, kind, path)
    remove(host, 'dir', STATE_DIR, quiet=True)   # /var/lib/robot, with the last robot
    if live_systemd:
        host.run(['systemctl', 'daemon-reload'])
        for unit in units:
            host.run(['systemctl', 'reset-failed', unit], check=False)
    if any(p.startswith(RULES_DIR + '/') for _, p in entries) and not host.staging:
        if host.dry_run or host.udevd_running():
            host.run(['udevadm', 'control', '--reload'])
    if host.staging:
        host.say('staging root %s: no systemctl, udevadm or nft calls' % host.root)


# ---- the running firewall: the allow-list for one match (not persistent) ----

def nft(*args):
    """(returncode, output) of nft ARGS on this machine (its current network namespace)."""
    try:
        r = subprocess.run([NFT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True)
    except OSError as e:
        return 127, str(e)
    return r.returncode, r.stdout


def table_loaded(robot):
    return nft('list', 'table', 'inet', table_name(robot))[0] == 0


def require_table(robot):
    if not os.path.exists(NFT):
        raise ConfigError('%s missing: apt-get install nftables (make deps), then make install-robot ROBOT=%s'
                          % (NFT, robot))
    if not table_loaded(robot):
        raise ConfigError('the firewall of %s is not installed/running (no nftables table inet %s): '
                          'make install-robot ROBOT=%s, or systemctl start %s'
                          % (robot, table_name(robot), robot, firewall_unit_name(robot)))


def element(addr):
    try:
        net = ipv4_network(addr)
    except ValueError:
        raise ConfigError('%r is not an IPv4 address or network (a.b.c.d or a.b.c.0/24)' % addr)
    return str(net) if net.prefixlen < 32 else str(net.network_address)


def covering(robot, elem):
    """The element of the running set `allowed` that holds elem, or None."""
    rc, out = nft('get', 'element', 'inet', table_name(robot), 'allowed', '{', elem, '}')
    if rc:
        return None
    m = re.search(r'elements\s*=\s*\{\s*([^}]*?)\s*\}', out)
    return m.group(1) if m else elem


def status(robot, out=sys.stdout):
    """Prints the running set `allowed` and the ros_dropped counter; returns (elements, packets, bytes)."""
    require_table(robot)
    table = table_name(robot)
    rc, text = nft('list', 'set', 'inet', table, 'allowed')
    m = re.search(r'elements\s*=\s*\{([^}]*)\}', text)
    elements = [e.strip() for e in m.group(1).split(',')] if m else []
    rc, text = nft('list', 'counter', 'inet', table, 'ros_dropped')
    m = re.search(r'packets\s+(\d+)\s+bytes\s+(\d+)', text)
    packets, nbytes = (int(m.group(1)), int(m.group(2))) if m else (0, 0)
    out.write('firewall of %s (nftables table inet %s):\n' % (robot, table))
    out.write('  allowed to the ROS ports: %s\n' % (', '.join(elements) or '(none)'))
    out.write('  ros_dropped: %d packets, %d bytes (to the ROS ports from anywhere else)\n' % (packets, nbytes))
    return elements, packets, nbytes


def allow(robot, addr, out=sys.stdout):
    """Adds addr to the running set `allowed` (until the firewall is reloaded or the computer reboots)."""
    elem = element(addr)
    require_table(robot)
    held = covering(robot, elem)
    if held is not None:
        out.write('%s is already allowed (%s)\n' % (elem, held))
    else:
        rc, text = nft('add', 'element', 'inet', table_name(robot), 'allowed', '{', elem, '}')
        if rc:
            raise ConfigError('nft add element %s: %s' % (elem, ' '.join(text.split())))
        out.write('allowed %s until the next reboot or reinstall (make deny-laptop ROBOT=%s ADDR=%s takes it '
                  'out)\n' % (elem, robot, addr))
    return status(robot, out)


def deny(robot, addr, out=sys.stdout):
    """Deletes addr from the running set `allowed`; connections already open stay until closed."""
    elem = element(addr)
    require_table(robot)
    held = covering(robot, elem)
    if held is None:
        out.write('%s was not allowed\n' % elem)
    elif held != elem:
        raise ConfigError('%s is allowed as part of %s (loopback, the robot\'s own addresses or '
                          'config/%s.yaml computer/network/allow): change the config and make install-robot'
                          % (elem, held, robot))
    else:
        rc, text = nft('delete', 'element', 'inet', table_name(robot), 'allowed', '{', elem, '}')
        if rc:
            raise ConfigError('nft delete element %s: %s' % (elem, ' '.join(text.split())))
        out.write('denied %s (its connections already open stay until they close; systemctl restart '
                  'robot-%s closes them)\n' % (elem, robot))
    return status(robot, out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('action', choices=['install', 'uninstall', 'allow', 'deny', 'status'])
    ap.add_argument('robot')
    ap.add_argument('address', nargs='?', help='allow/deny: an IPv4 address or network (the laptop)')
    ap.add_argument('--root', default='/', help='install under this staging root; no systemctl/udevadm/ip calls')
    ap.add_argument('--dry-run', action='store_true', help='print what it would do, change nothing')
    ap.add_argument('--start', action='store_true', help='install: start robot-ROBOT.service now')
    ap.add_argument('--repo', default=REPO, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if not re.match(r'^[A-Za-z0-9_-]+$', args.robot):
        sys.stderr.write('robot_install: %r is not a robot name\n' % args.robot)
        return 1
    if args.action in ('allow', 'deny', 'status'):
        if (args.address is None) != (args.action == 'status') or args.root != '/' or args.dry_run:
            sys.stderr.write('robot_install: %s ROBOT%s (no --root, --dry-run)\n'
                             % (args.action, '' if args.action == 'status' else ' ADDR'))
            return 2
        try:
            if args.address is not None:
                element(args.address)   # a wrong address first, root or not
            if os.geteuid() != 0:
                raise ConfigError('run as root (nft)')
            if args.action == 'status':
                status(args.robot)
            else:
                (allow if args.action == 'allow' else deny)(args.robot, args.address)
        except ConfigError as e:
            sys.stderr.write('robot_install: %s\n' % e)
            return 1
        return 0
    if args.address is not None:
        sys.stderr.write('robot_install: %s takes no address\n' % args.action)
        return 2
    host = Host(args.root, args.dry_run)
    if not host.staging and not host.dry_run and os.geteuid() != 0:
        sys.stderr.write('robot_install: run as root (or --root DIR to stage)\n')
        return 1
    try:
        if args.action == 'install':
            install(args.robot, host, args.start, os.path.abspath(args.repo))
        else:
            uninstall(args.robot, host, os.path.abspath(args.repo))
    except ConfigError as e:
        sys.stderr.write('robot_install: %s\n' % e)
        return 1
    if host.failed:
        sys.stderr.write('robot_install: %s done, but %d command(s) failed: %s\n'
                         % (args.action, len(host.failed), '; '.join(host.failed)))
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
