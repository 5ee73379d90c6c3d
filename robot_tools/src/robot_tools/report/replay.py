"""`make replay BAG=... [ROBOT=eurobot2009] [THROUGH=localization] [RATE=1] [SIM=1]`: launch/replay.launch
on a recorded match, and its verdict as the exit code (roslaunch itself always exits 0): the
player's line `replay: reproduced R of N recorded estimates (P %) ...` is printed, and the exit
code is 3 when, through the localization, fewer than 95 % were reproduced."""
import argparse
import os
import subprocess
import sys

from robot_tools.paths import ROOT


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('bag')
    ap.add_argument('--robot', default='eurobot2009')
    ap.add_argument('--through', default='localization', choices=('localization', 'hal'))
    ap.add_argument('--rate', default='1.0')
    ap.add_argument('--sim', action='store_true', help='the bag was recorded in simulation')
    args = ap.parse_args()
    if not os.path.isfile(args.bag):
        sys.exit('replay: BAG=%s: no such file' % args.bag)
    cmd = ['roslaunch', os.path.join(ROOT, 'launch', 'replay.launch'), 'bag:=' + os.path.abspath(args.bag),
           'robot:=' + args.robot, 'through:=' + args.through, 'rate:=' + args.rate,
           'sim:=' + ('true' if args.sim else 'false')]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                            errors='replace')
    unfaithful = False
    for line in proc.stdout:
        sys.stdout.write(line)
        unfaithful = unfaithful or line.startswith('bag_replay: fewer than')
    rc = proc.wait()
    return 3 if unfaithful else rc


if __name__ == '__main__':
    sys.exit(main())
