"""The files make install-robot puts on the robot's computer, as texts and Items (path, content
or link target, directory): the CAN units, the udev rules, the nftables rules and the unit that
loads them, the robot's service, and items(), all of them in install order. Nothing here
touches the host; robot_tools.install.apply puts them in place."""
import ipaddress
import os
import shlex

from robot_core.network_settings import ipv4_network

from robot_tools.install.plan import DEFAULT_NETWORK, PORT_RANGE_FILE, REPO, plan, read_port_range

UNIT_DIR = '/etc/systemd/system'
RULES_DIR = '/etc/udev/rules.d'
STATE_DIR = '/var/lib/robot'
IP = '/sbin/ip'
NFT = '/usr/sbin/nft'
NFT_DIR = '/etc/robot'
PATH = '/usr/bin:/bin:/usr/sbin:/sbin'


class Item(object):
    """One thing on the disk: a file (content), a symlink (target) or a directory."""

    def __init__(self, path, content=None, link=None, directory=False, mode=0o644):
        self.path, self.content, self.link, self.directory, self.mode = path, content, link, directory, mode

    def kind(self):
        return 'dir' if self.directory else 'link' if self.link is not None else 'file'


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
