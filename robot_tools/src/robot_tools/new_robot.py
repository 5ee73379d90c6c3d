"""`make new-robot NAME=... FROM=skeleton|eurobot2009|logion`: a new robot's files from a template.

    scripts/new_robot.py NAME --from TEMPLATE [--remove]

Writes, each a copy of the template's with its name replaced by NAME:
  config/NAME.yaml, config/NAME.sim.yaml        the robot and its simulation
  launch/NAME.launch                            the template's launch file (its `robot` argument's default)
  robot_description/rviz/NAME.rviz                (the URDF is written from config/NAME.yaml's robot: block)
  config/tune/NAME.yaml                         when the template has one
then checks the new config (robot_description/scripts/check_config) and says what to edit next.
It refuses a NAME that is taken or not a plain lowercase identifier, and writes nothing then.
--remove deletes those files of NAME again (never a template's).
"""
import argparse
import os
import re
import subprocess
import sys

from robot_tools.paths import ROOT
TEMPLATES = ('skeleton', 'eurobot2009', 'logion')
NAME_RULE = re.compile(r'^[a-z][a-z0-9_]{1,31}$')

# What a team edits after the copy, in the order that gets a robot driving (docs/adding.md, "Adding a robot").
NEXT_STEPS = {
    'table': [
        'config/{n}.yaml robot: (radius, wheel_radius, track_width, encoder_ticks_per_rev, links): the drive, '
        'odometry, driver and localization read them from there, and the URDF is written from it',
        'config/{n}.sim.yaml sim/world/robot: what only the simulator needs (motors\' dynamics, switches, '
        'collectors, noise); its outline, wheels and ranger mounts come from robot: above',
        'the start zone (table/start_zones, the robot in it) decides the colour: hal/localization/initial_pose, '
        'sim/world/robot start, sim/world/opponent start and hal/hmi side must all agree with it',
        'hcl: the boards of your robot, with their sim/firmware emulators; hal: the devices',
        'brain: its strategy (smart_brain/src/smart_brain/strategies)',
    ],
    'desk': [
        'config/{n}.yaml hcl: the boards of your robot, and config/{n}.sim.yaml their emulators',
        'hal: the devices on them; brain: its strategy (smart_brain/src/smart_brain/strategies)',
        'config/{n}.yaml robot/links: its frames (the URDF is written from them)',
    ],
}


def files_of(robot):
    """(path relative to ROOT, required) of every file a robot has."""
    return [('config/%s.yaml' % robot, True), ('config/%s.sim.yaml' % robot, True),
            ('launch/%s.launch' % robot, True), ('robot_description/rviz/%s.rviz' % robot, True), ('config/tune/%s.yaml' % robot, False)]


def renamed(text, template, name):
    """The template's name replaced as a word (not inside driver_sim_logion, a test's name)."""
    return re.sub(r'(?<![A-Za-z0-9_])%s(?![A-Za-z0-9_])' % re.escape(template), name, text)


def refuse(msg):
    sys.exit('new-robot: ' + msg)


def create(name, template):
    if template not in TEMPLATES:
        refuse('FROM=%s: allowed values: %s' % (template, ', '.join(TEMPLATES)))
    if not NAME_RULE.match(name):
        refuse("NAME=%s: a robot's name is 2-32 characters of a-z, 0-9 and _, starting with a letter "
               "(it names files, a ROS parameter and a systemd unit)" % name)
    taken = [p for p, _ in files_of(name) if os.path.exists(os.path.join(ROOT, p))]
    if taken:
        refuse('NAME=%s is taken: %s exist(s); pick another name or remove it (scripts/new_robot.py %s --remove)'
               % (name, ', '.join(taken), name))
    written = []
    for (src, required), (dst, _) in zip(files_of(template), files_of(name)):
        src_path = os.path.join(ROOT, src)
        if not os.path.exists(src_path):
            if required:
                refuse('the template %s has no %s' % (template, src))
            continue
        with open(src_path) as f:
            text = renamed(f.read(), template, name)
        if dst.endswith('.yaml') and dst.startswith('config/%s' % name):
            text = '# %s: made from %s by make new-robot.\n' % (name, template) + text
        with open(os.path.join(ROOT, dst), 'w') as f:
            f.write(text)
        written.append(dst)
    print('new-robot: wrote ' + ', '.join(written))
    check = subprocess.run([os.path.join(ROOT, 'robot_description', 'scripts', 'check_config'), name])
    kind = 'table' if 'start_zones' in open(os.path.join(ROOT, 'config', name + '.yaml')).read() else 'desk'
    print('new-robot: next, edit (each run of make check-config ROBOT=%s checks them in seconds):' % name)
    for step in NEXT_STEPS[kind]:
        print('  - ' + step.format(n=name))
    print('new-robot: run it: make run ROBOT=%s   (remove it: scripts/new_robot.py %s --remove)' % (name, name))
    return check.returncode


def remove(name):
    if name in TEMPLATES:
        refuse('%s is a template, not removed' % name)
    gone = []
    for path, _ in files_of(name):
        full = os.path.join(ROOT, path)
        if os.path.exists(full):
            os.remove(full)
            gone.append(path)
    print('new-robot: removed ' + (', '.join(gone) if gone else 'nothing (no such robot)'))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('name')
    ap.add_argument('--from', dest='template', default='skeleton', help='one of: ' + ', '.join(TEMPLATES))
    ap.add_argument('--remove', action='store_true', help="delete NAME's files")
    args = ap.parse_args()
    sys.exit(remove(args.name) if args.remove else create(args.name, args.template))


if __name__ == '__main__':
    main()
