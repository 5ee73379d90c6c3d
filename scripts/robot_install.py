#!/usr/bin/python3
"""Sets the robot's own computer up for one robot, and undoes it (make install-robot /
make uninstall-robot; README "The robot's computer").

    robot_install.py install ROBOT [--root DIR] [--dry-run] [--start]
    robot_install.py uninstall ROBOT [--root DIR] [--dry-run]

What it installs comes from config/ROBOT.yaml, section `computer:` (none: only the service):
  * per CAN interface of `computer: can:`, a oneshot unit robot-can-IFACE.service bound to the
    interface's device unit, enabled for it (the interface comes up at its bitrate at boot and
    whenever the adapter appears), started now when the interface exists;
  * /etc/udev/rules.d/99-robot-ROBOT.rules: per `computer: devices:` entry, a rule giving the
    USB device the stable name its board block uses (hcl/<board>/port or device, /dev/robot/x);
  * robot-ROBOT.service: `roslaunch launch/ROBOT.launch sim:=false` at boot, enabled, started
    only with --start;
  * /var/lib/robot/ROBOT/: the service's home (ROS_HOME, ROS_LOG_DIR) and installed.txt, the
    manifest uninstall removes (files, symlinks, then the directories it created, when empty).
With --root DIR everything goes under DIR and nothing on this machine is called (systemctl,
udevadm, ip); --dry-run only prints what it would do. One function per installed thing: each
returns the Items (files, enable symlinks, directories) it puts in place.
"""
import argparse
import os
import re
import shlex
import subprocess
import sys

import yaml

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..'))
UNIT_DIR = '/etc/systemd/system'
RULES_DIR = '/etc/udev/rules.d'
STATE_DIR = '/var/lib/robot'
IP = '/sbin/ip'
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
    return {'can': can, 'devices': devices}


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


def robot_service(robot, can, repo=REPO):
    """robot-ROBOT.service: the robot's launch on the real robot, at boot, restarted on failure."""
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
        'Wants=network-online.target' + (' ' + cans if cans else ''),
        'After=network-online.target' + (' ' + cans if cans else ''),
        '',
        '[Service]',
        'Type=simple',
        'Environment=PATH=%s' % PATH,
        'Environment=HOME=%s ROS_HOME=%s ROS_LOG_DIR=%s' % (home, os.path.join(home, 'ros'), os.path.join(home, 'log')),
        'Environment=PYTHONNOUSERSITE=1 ROS_PYTHON_VERSION=3',
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


def items(robot, config, repo=REPO):
    """Everything install puts in place, in order (the manifest is written last)."""
    p = plan(robot, config)
    home = state_dir(robot)
    out = [Item(STATE_DIR, directory=True), Item(home, directory=True),
           Item(os.path.join(home, 'ros'), directory=True), Item(os.path.join(home, 'log'), directory=True)]
    for iface, bitrate in sorted(p['can'].items()):
        out += can_unit(robot, iface, bitrate)
    out += udev_rules(robot, p['devices'])
    out += robot_service(robot, p['can'], repo)
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
        host.say('staging root %s: no systemctl, udevadm or ip calls' % host.root)
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
    if live_systemd:
        for unit in units:
            host.run(['systemctl', 'stop', unit], check=False)
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
        host.say('staging root %s: no systemctl or udevadm calls' % host.root)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('action', choices=['install', 'uninstall'])
    ap.add_argument('robot')
    ap.add_argument('--root', default='/', help='install under this staging root; no systemctl/udevadm/ip calls')
    ap.add_argument('--dry-run', action='store_true', help='print what it would do, change nothing')
    ap.add_argument('--start', action='store_true', help='install: start robot-ROBOT.service now')
    ap.add_argument('--repo', default=REPO, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if not re.match(r'^[A-Za-z0-9_-]+$', args.robot):
        sys.stderr.write('robot_install: %r is not a robot name\n' % args.robot)
        return 1
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
