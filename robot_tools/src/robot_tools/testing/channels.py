"""The channels a test takes that another test could take too (a loopback port for its emulators,
a robot launch's default CAN bus, emulator directory or webcam port): two tests that share one
never run side by side."""
import glob
import os
import re
import xml.etree.ElementTree as ET

from robot_tools.paths import ROOT

CHANNEL_ARGS = ('can_bus', 'sim_dir', 'camera_port')


def robot_launches():
    """The launch files with simulation channel arguments (the CAN bus, the emulators' directory,
    the webcam port), by file name: a simulation on their defaults owns those channels."""
    found = {}
    for path in glob.glob(os.path.join(ROOT, 'launch', '*.launch')):
        names = {a.get('name') for a in ET.parse(path).getroot().iter('arg')} & set(CHANNEL_ARGS)
        if names:
            found[os.path.basename(path)] = names
    return found


def test_texts(target, test_file, packages):
    """The text of what a test runs: its .test file, the launch and YAML files it includes or
    loads (not the robots' own launch files), and the test scripts beside it that the .test or a
    nosetests target names."""
    texts, files = [], []
    if test_file:
        files.append(test_file)
    m = re.match(r'run_tests_system_tests_nosetests_(\S+\.py)$', target)
    if m:
        files += glob.glob(os.path.join(packages.get('system_tests', ''), m.group(1).replace('.', '/', 1)))
    seen = set()
    while files:
        path = files.pop()
        if path in seen or not os.path.exists(path):
            continue
        seen.add(path)
        text = open(path).read()
        texts.append(text)
        if path.endswith(('.test', '.launch')):
            here = os.path.dirname(path)
            loaded = re.findall(r'<include file="([^"]+)"', text) + re.findall(r'<rosparam [^>]*file="([^"]+)"', text)
            for inc in loaded:
                inc = re.sub(r'\$\(find (\w+)\)', lambda g: packages.get(g.group(1), ''), inc)
                inc = os.path.normpath(inc.replace('$(dirname)', here))
                if os.path.dirname(inc) != os.path.join(ROOT, 'launch'):
                    files.append(inc)
            for script in re.findall(r'<test [^>]*type="([^"]+\.py)"', text):
                files += glob.glob(os.path.join(packages.get('system_tests', ''), 'scripts', script))
    return texts


def fixed_channels(target, test_file, packages, launches):
    """The channels a test takes that another test could take too: the loopback ports it gives
    its emulators, and each robot launch's default channels it starts that robot on. Two tests
    that share one never run together."""
    text = '\n'.join(test_texts(target, test_file, packages))
    found = set(re.findall(r'127\.0\.0\.1:(\d+)', text))
    found |= set(re.findall(r'name="camera_port" value="(\d+)"', text))
    for launch, names in launches.items():
        if launch in text:
            found |= {'%s %s' % (launch, n) for n in names if n + ':=' not in text and 'name="%s"' % n not in text}
            # and the ports its config and sim overlay fix (the skeleton's board), whatever the arguments
            robot = launch[:-len('.launch')]
            for config in ('%s.yaml' % robot, '%s.sim.yaml' % robot):
                path = os.path.join(ROOT, 'config', config)
                if os.path.exists(path):
                    found |= set(re.findall(r'127\.0\.0\.1:(\d+)', open(path).read()))
    return found
