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

This module is the command. The config read and checked: robot_tools.install.plan; the installed
files: host_files; putting them in place and removing them: apply; allow/deny/status:
running_firewall.
"""
import argparse
import os
import re
import sys

from robot_tools.install.apply import Host, install, uninstall
from robot_tools.install.plan import REPO, ConfigError
from robot_tools.install.running_firewall import allow, deny, element, status


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
