"""The side effects of make install-robot / uninstall-robot on the host: Host (the file system
under a root, the commands run, or only said in a dry run), putting the items of
robot_tools.install.host_files in place with their manifest, then systemctl, udevadm, ip and
nft; and undoing it from the manifest."""
import os
import subprocess
import sys

from robot_tools.install.host_files import (NFT, RULES_DIR, STATE_DIR, can_unit_name, firewall_unit_name, items,
                                            manifest_path, nft_path, service_name, table_name)
from robot_tools.install.plan import REPO, ConfigError, load_config
from robot_tools.install.running_firewall import table_loaded


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
