"""make install-robot / uninstall-robot (scripts/robot_install.py) into a temporary staging root:
the files' contents against the values of config/ROBOT.yaml (read here, never copied), the units
through systemd-analyze verify, uninstall leaving the root empty, and the configuration errors
(exit 1 with one line). Nothing on this machine is touched: no systemctl, udevadm or ip."""
import copy
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import yaml

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
SCRIPT = os.path.join(ROOT, 'scripts', 'robot_install.py')
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
import robot_install  # noqa: E402

ENV = dict(os.environ, PATH='/usr/bin:/bin:/usr/sbin:/sbin:' + os.environ.get('PATH', ''))


def config(robot):
    with open(os.path.join(ROOT, 'config', robot + '.yaml')) as f:
        return yaml.safe_load(f)


def run(*args, **kw):
    return subprocess.run([sys.executable, SCRIPT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, env=ENV, **kw)


def unit(text):
    """{section: [(key, value), ...]} of a unit file."""
    out, section = {}, None
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith('#'):
            continue
        if line.startswith('['):
            section = line.strip('[]')
            out.setdefault(section, [])
        else:
            key, value = line.split('=', 1)
            out[section].append((key, value))
    return out


def values(u, section, key):
    return [v for k, v in u.get(section, []) if k == key]


def tree(root):
    return sorted(os.path.relpath(os.path.join(d, n), root) for d, dirs, files in os.walk(root) for n in dirs + files)


class InstallTest(unittest.TestCase):
    def setUp(self):
        self.root = tempfile.mkdtemp(prefix='robot_install_')

    def tearDown(self):
        shutil.rmtree(self.root, ignore_errors=True)

    def at(self, path):
        return os.path.join(self.root, path.lstrip('/'))

    def read(self, path):
        with open(self.at(path)) as f:
            return f.read()

    def install(self, robot):
        r = run('install', robot, '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn('no systemctl, udevadm or ip calls', r.stdout)
        return r

    def uninstall_leaves_root_empty(self, robot):
        r = run('uninstall', robot, '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(tree(self.root), [], r.stdout)

    def check_robot(self, robot):
        cfg = config(robot)
        computer = cfg.get('computer') or {}
        can = {iface: spec['bitrate'] for iface, spec in (computer.get('can') or {}).items()}
        devices = computer.get('devices') or {}
        self.install(robot)
        units = '/etc/systemd/system'

        # The robot's service: its launch on the real robot, the workspace's environment.
        service = self.read('%s/robot-%s.service' % (units, robot))
        u = unit(service)
        exec_start = values(u, 'Service', 'ExecStart')
        self.assertEqual(len(exec_start), 1, service)
        self.assertIn('source %s/devel/setup.bash' % ROOT, exec_start[0])
        self.assertIn('exec roslaunch %s/launch/%s.launch sim:=false' % (ROOT, robot), exec_start[0])
        self.assertEqual(values(u, 'Service', 'Restart'), ['on-failure'])
        env = ' '.join(values(u, 'Service', 'Environment'))
        self.assertIn('PATH=/usr/bin:', env)
        self.assertIn('ROS_HOME=/var/lib/robot/%s/' % robot, env)
        self.assertIn('ROS_LOG_DIR=/var/lib/robot/%s/' % robot, env)
        self.assertEqual(values(u, 'Service', 'StandardOutput'), ['journal'])
        after = ' '.join(values(u, 'Unit', 'After')).split()
        self.assertIn('network-online.target', after)
        for iface in can:
            self.assertIn('robot-can-%s.service' % iface, after)
        self.assertEqual(values(u, 'Install', 'WantedBy'), ['multi-user.target'])
        link = self.at('%s/multi-user.target.wants/robot-%s.service' % (units, robot))
        self.assertEqual(os.readlink(link), '%s/robot-%s.service' % (units, robot))   # enabled

        # A oneshot unit per CAN interface, bound to and enabled for its device, at its bitrate.
        boards = robot_install.can_boards(cfg)
        self.assertEqual(set(boards.values()), set(can), 'computer/can != the hcl blocks\' socketcan buses')
        for iface, bitrate in can.items():
            u = unit(self.read('%s/robot-can-%s.service' % (units, iface)))
            device = 'sys-subsystem-net-devices-%s.device' % iface
            self.assertEqual(values(u, 'Unit', 'BindsTo'), [device])
            self.assertEqual(values(u, 'Service', 'Type'), ['oneshot'])
            self.assertEqual(values(u, 'Service', 'ExecStart'), [
                '-/sbin/ip link set %s down' % iface,
                '/sbin/ip link set %s type can bitrate %d restart-ms 100' % (iface, bitrate),
                '/sbin/ip link set %s up' % iface])
            self.assertEqual(values(u, 'Install', 'WantedBy'), [device])
            self.assertTrue(os.path.islink(self.at('%s/%s.wants/robot-can-%s.service' % (units, device, iface))))

        # udev: each device gets the name its board block uses.
        rules = '/etc/udev/rules.d/99-robot-%s.rules' % robot
        if devices:
            text = self.read(rules)
            lines = [l for l in text.splitlines() if l and not l.startswith('#')]
            self.assertEqual(len(lines), len(devices), text)
            for board, spec in devices.items():
                block = cfg['hcl'][board]
                path = block.get('port', block.get('device'))
                self.assertTrue(path.startswith('/dev/robot/'), path)
                rule = [l for l in lines if 'SYMLINK+="%s"' % path[len('/dev/'):] in l]
                self.assertEqual(len(rule), 1, text)
                self.assertIn('SUBSYSTEM=="%s"' % spec['subsystem'], rule[0])
                self.assertIn('ATTRS{idVendor}=="%s"' % spec['vendor'], rule[0])
                self.assertIn('ATTRS{idProduct}=="%s"' % spec['product'], rule[0])
                if spec['subsystem'] == 'input':
                    self.assertIn('KERNEL=="js*"', rule[0])
        else:
            self.assertFalse(os.path.exists(self.at(rules)))

        self.verify_units(robot)
        manifest = self.read('/var/lib/robot/%s/installed.txt' % robot)
        self.assertIn('file /etc/systemd/system/robot-%s.service' % robot, manifest)
        self.uninstall_leaves_root_empty(robot)

    def verify_units(self, robot):
        """systemd-analyze verify: it works on unit files in any directory (it adds the file's
        directory to the search path), without a running systemd, and checks the directives and
        that ExecStart's programs exist. Its warnings exit 0: any output is a failure here."""
        if not shutil.which('systemd-analyze', path=ENV['PATH']):
            self.skipTest('no systemd-analyze here')
        units = self.at('/etc/systemd/system')
        files = sorted(os.path.join(units, f) for f in os.listdir(units) if f.endswith('.service'))
        r = subprocess.run(['systemd-analyze', 'verify'] + files, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, env=ENV, cwd=units)
        # No sysinit.target etc. where systemd is not installed as a whole: that is the host, not us.
        problems = [l for l in r.stdout.splitlines() if 'robot-' in l or ':' in l and units in l]
        self.assertEqual((r.returncode, problems), (0, []), r.stdout)

    def test_eurobot2009(self):
        self.check_robot('eurobot2009')

    def test_logion(self):
        self.check_robot('logion')

    def test_skeleton_has_no_computer_section_just_the_service(self):
        self.assertNotIn('computer', config('skeleton'))
        self.install('skeleton')
        self.assertEqual(sorted(os.listdir(self.at('/etc/systemd/system'))),
                         ['multi-user.target.wants', 'robot-skeleton.service'])
        self.assertFalse(os.path.exists(self.at('/etc/udev')))
        self.uninstall_leaves_root_empty('skeleton')

    def test_dry_run_changes_nothing(self):
        r = run('install', 'eurobot2009', '--root', self.root, '--dry-run')
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('would write /etc/systemd/system/robot-eurobot2009.service', r.stdout)
        self.assertEqual(tree(self.root), [])

    def test_reinstall_and_two_robots_share_the_root(self):
        self.install('eurobot2009')
        self.install('eurobot2009')
        self.install('logion')
        run('uninstall', 'eurobot2009', '--root', self.root)
        self.assertFalse(os.path.exists(self.at('/etc/systemd/system/robot-eurobot2009.service')))
        self.assertTrue(os.path.exists(self.at('/etc/systemd/system/robot-logion.service')))
        self.assertTrue(os.path.exists(self.at('/etc/udev/rules.d/99-robot-logion.rules')))
        r = run('uninstall', 'logion', '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stderr)
        # The directories eurobot2009's install created and logion's used stay (empty): no file does.
        left = [p for p in tree(self.root) if not os.path.isdir(os.path.join(self.root, p))]
        self.assertEqual(left, [])
        self.assertFalse(os.path.exists(self.at('/var/lib/robot')), 'removed with the last robot')

    def test_uninstall_without_manifest_removes_what_install_would(self):
        self.install('eurobot2009')
        os.remove(self.at('/var/lib/robot/eurobot2009/installed.txt'))
        r = run('uninstall', 'eurobot2009', '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('no /var/lib/robot/eurobot2009/installed.txt', r.stdout)
        left = [p for p in tree(self.root) if not os.path.isdir(os.path.join(self.root, p))]
        self.assertEqual(left, [])

    def test_does_not_overwrite_a_file_it_did_not_install(self):
        path = self.at('/etc/systemd/system/robot-can-can0.service')
        os.makedirs(os.path.dirname(path))
        with open(path, 'w') as f:
            f.write('[Service]\nExecStart=/bin/true\n')
        r = run('install', 'eurobot2009', '--root', self.root)
        self.assertEqual(r.returncode, 1)
        self.assertIn('robot-can-can0.service exists and was not installed for eurobot2009', r.stderr)


class ConfigErrorTest(unittest.TestCase):
    """A wrong `computer:` section: exit 1, one line naming the value, nothing installed."""

    def setUp(self):
        self.repo = tempfile.mkdtemp(prefix='robot_install_repo_')
        os.mkdir(os.path.join(self.repo, 'config'))
        self.root = os.path.join(self.repo, 'root')

    def tearDown(self):
        shutil.rmtree(self.repo, ignore_errors=True)

    def refused(self, cfg, message):
        with open(os.path.join(self.repo, 'config', 'broken.yaml'), 'w') as f:
            yaml.safe_dump(cfg, f)
        r = run('install', 'broken', '--root', self.root, '--repo', self.repo)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn(message, r.stderr)
        self.assertFalse(os.path.exists(self.root) and tree(self.root), 'installed something')

    def test_can_bus_without_bitrate(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        del cfg['computer']['can']['can0']
        board = sorted(robot_install.can_boards(cfg))[0]
        self.refused(cfg, 'hcl/%s/bus is socketcan://can0 but computer/can has no bitrate for can0' % board)

    def test_can_bus_and_no_computer_section(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        del cfg['computer']
        self.refused(cfg, 'computer/can has no bitrate for can0')

    def test_bitrate_not_a_number(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        cfg['computer']['can']['can0']['bitrate'] = '1M'
        self.refused(cfg, "computer/can/can0/bitrate: '1M' is not a bitrate")

    def test_device_of_no_board(self):
        cfg = copy.deepcopy(config('logion'))
        cfg['computer']['devices']['lidar'] = {'subsystem': 'tty', 'vendor': '10c4', 'product': 'ea60'}
        self.refused(cfg, 'computer/devices/lidar: there is no board block hcl/lidar')

    def test_device_path_not_under_dev(self):
        cfg = copy.deepcopy(config('logion'))
        cfg['hcl']['beacons']['port'] = '/tmp/beacons.tty'
        self.refused(cfg, "hcl/beacons/port is '/tmp/beacons.tty', not a path under /dev/")

    def test_bad_usb_id(self):
        cfg = copy.deepcopy(config('logion'))
        cfg['computer']['devices']['joystick']['vendor'] = 'logitech'
        self.refused(cfg, "computer/devices/joystick/vendor: 'logitech' is not a 4-digit hex USB id")


if __name__ == '__main__':
    unittest.main()
