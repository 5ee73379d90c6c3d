#!/usr/bin/env python3
"""Runs the workspace's test targets (catkin's run_tests_<package>_<kind>_<name>) one after the
other, or on a pool of --jobs slots, longest first, and says what each one cost.

Tests run side by side within a CPU budget. Each test's load is the cores it keeps busy (its
CPU seconds over its wall seconds in test/test_costs.json, a quiet one-at-a-time run committed
with the tests; else as this tree's build/test_durations.json last measured it). A test starts
when the loads of the tests running plus its own stay within --budget (0.85 of the cores): a
stack stretched past the cores misses its own watchdogs (`process /brain: not answering within
0.20 s`). The HEAVY ones (matches played as fast as the machine goes, a VM) and the RUN_ALONE
ones run with nothing beside them: they take every core they get, and a stack's CPU grows with
its wall time, so a test beside one costs it more than it saves. Two tests that share an
emulator port or a robot's default channels never run together, and each test keeps its own ROS
master (rostest picks a free port). TEST_JOBS=1 runs one test at a time.

Prints one line per test as it ends (wall seconds, CPU seconds of the test and everything it
started, result), the output of a test that failed, and a closing line; writes the figures to
build/test_durations.json, which the next run on this tree orders by.

  test_pool.py [--jobs N] [--budget CORES] [--quick] [--only REGEX] [--list] [--save-costs]
Called by run_tests.sh with the workspace sourced, once the test binaries are built.
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(ROOT, 'build')
DURATIONS = os.path.join(BUILD, 'test_durations.json')
COSTS = os.path.join(ROOT, 'test', 'test_costs.json')

# Tests that measure latency or rates (anything beside them would measure the machine), or that
# change what the others read.
RUN_ALONE = {
    'run_tests_system_tests_rostest_launch_reflex_latency.test': 'measures the reflex latency p99',
    'run_tests_system_tests_nosetests_unit.test_new_robot.py':
        'adds robots to the checkout (config/, launch/) while it runs: a test listing the robots would see them',
}
# Tests outside rostest that play simulated matches or boot a VM, with their expected wall seconds
# (the rest of the gtests, nosetests and fuzz targets take seconds).
SIMULATED = {
    'run_tests_system_tests_nosetests_unit.test_new_robot.py': 300,
    'run_tests_system_tests_vm_can_socketcan': 150,
}
# Tests that keep the cores busy for minutes (matches played as fast as the machine goes, a VM in
# software emulation): they run with nothing beside them.
HEAVY = {'run_tests_system_tests_rostest_launch_%s.test' % name for name in (
    'calibrate_recovery_eurobot2009', 'chaos_smoke', 'matches_smoke', 'matches_cluster', 'tune_smoke',
    'soak_smoke', 'match_respawn_eurobot2009', 'match_blocked_eurobot2009', 'match_blocked_logion',
    'match_faults_eurobot2009')} | set(SIMULATED)
QUICK_KINDS = ('gtest', 'nosetests', 'fuzz')


def targets():
    """Every run_tests_<pkg>_<kind>_<name> target the build knows."""
    out = subprocess.run(['make', '-C', BUILD, 'help'], capture_output=True, text=True, check=True).stdout
    names = set(re.findall(r'\b(run_tests_[A-Za-z0-9_]+?_(?:gtest|nosetests|fuzz|rostest|vm)_\S+)', out))
    return sorted(names)


def package_dirs():
    dirs = {}
    for xml in glob.glob(os.path.join(ROOT, 'src', '*', 'package.xml')):
        name = ET.parse(xml).getroot().findtext('name')
        dirs[name] = os.path.realpath(os.path.dirname(xml))
    return dirs


def rostest_file(target, packages):
    """The .test file of a rostest target: its path in the package, '/' spelled '_' in the name."""
    for pkg, d in packages.items():
        prefix = 'run_tests_%s_rostest_' % pkg
        if target.startswith(prefix):
            flat = target[len(prefix):]
            for path in glob.glob(os.path.join(d, '**', '*.test'), recursive=True):
                if os.path.relpath(path, d).replace('/', '_') == flat:
                    return path
    return None


def time_limit(test_file):
    """The sum of the file's <test time-limit=...> (rostest's default is 60 s)."""
    root = ET.parse(test_file).getroot()
    return sum(float(t.get('time-limit', 60)) for t in root.iter('test'))


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


def estimate(target, test_file, history):
    if target in history:
        return history[target]['wall_s']
    if target in SIMULATED:
        return SIMULATED[target]
    if test_file:
        return time_limit(test_file) / 3.0  # the limits leave about 3x room
    return 10.0


def load(target, reference, history):
    """The cores a test keeps busy: its CPU over its wall time in the committed quiet run, else as
    this tree last measured it, else a guess on the safe side (a simulated one keeps a core and a
    half, anything else one). The reference comes first: a run that failed early or ran tests
    side by side measures less than the test needs."""
    h = reference.get(target) or history.get(target)
    if h and h['wall_s'] > 0:
        return min(h['cpu_s'] / h['wall_s'], float(os.cpu_count() or 1))
    return 1.5 if target in HEAVY else 1.0


def read_figures(path):
    """{target: {wall_s, cpu_s}} from a figures file, empty when there is none."""
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


def run(target, log_dir):
    """Starts one target; returns (process, log path, start time)."""
    log = os.path.join(log_dir, target + '.log')
    with open(log, 'w') as f:
        proc = subprocess.Popen(['make', '-C', BUILD, '-j1', target], stdout=f, stderr=subprocess.STDOUT,
                                cwd=ROOT)
    return proc, log, time.monotonic()


def result_file(target):
    """The JUnit file catkin's run_tests.py writes for a target (the first argument in its rule)."""
    for rule in glob.glob(os.path.join(BUILD, '*', 'CMakeFiles', target + '.dir', 'build.make')):
        m = re.search(r'run_tests\.py (\S+\.xml)', open(rule).read())
        if m:
            return m.group(1)
    return None


def result_files(target, test_file):
    """The JUnit files a target writes: catkin's, and for a rostest one per <test test-name=...>
    (rostest's own file says only whether the launch came up)."""
    path = result_file(target)
    if not path:
        return []
    files = [path]
    if test_file:
        files += [os.path.join(os.path.dirname(path), 'rosunit-%s.xml' % t.get('test-name'))
                  for t in ET.parse(test_file).getroot().iter('test')]
    return files


def result_failed(target, test_file):
    """True when one of the target's JUnit files is missing, unreadable or reports a failure or error."""
    files = result_files(target, test_file)
    for path in files:
        if not os.path.exists(path):
            return True
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError:
            return True
        suites = [root] if root.tag == 'testsuite' else list(root.iter('testsuite'))
        if any(int(s.get('errors', 0) or 0) + int(s.get('failures', 0) or 0) for s in suites):
            return True
    return not files


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    cores = os.cpu_count() or 1
    ap.add_argument('--jobs', type=int, default=int(os.environ.get('TEST_JOBS', cores)),
                    help='tests at once at most (default TEST_JOBS or the number of cores, %d)' % cores)
    ap.add_argument('--budget', type=float, default=0.85 * cores,
                    help='cores the tests running side by side may keep busy together (default %.2f)'
                    % (0.85 * cores))
    ap.add_argument('--quick', action='store_true', help='gtests, nosetests and fuzz targets only, no simulation')
    ap.add_argument('--only', help='run only the targets matching this regular expression')
    ap.add_argument('--list', action='store_true', help='print the targets in the order they would start')
    ap.add_argument('--save-costs', action='store_true',
                    help="write this tree's last measured figures to %s (after a quiet run with TEST_JOBS=1)"
                    % os.path.relpath(COSTS, ROOT))
    args = ap.parse_args()
    if args.save_costs:
        with open(DURATIONS) as f:
            measured = json.load(f)
        with open(COSTS, 'w') as f:
            json.dump({t: measured[t] for t in targets() if t in measured}, f, indent=1, sort_keys=True)
            f.write('\n')
        return 0

    packages = package_dirs()
    launches = robot_launches()
    reference, history = read_figures(COSTS), read_figures(DURATIONS)
    todo = []
    for t in targets():
        kind = re.match(r'run_tests_.+?_(gtest|nosetests|fuzz|rostest|vm)_', t).group(1)
        if args.quick and (kind not in QUICK_KINDS or t in SIMULATED):
            continue
        if args.only and not re.search(args.only, t):
            continue
        test_file = rostest_file(t, packages) if kind == 'rostest' else None
        todo.append({'target': t, 'file': test_file, 'estimate': estimate(t, test_file, {**reference, **history}),
                     'load': load(t, reference, history), 'alone': t in RUN_ALONE or t in HEAVY, 'ports': fixed_channels(t, test_file, packages, launches)})
    todo.sort(key=lambda x: -x['estimate'])
    if args.list:
        for x in todo:
            print('%7.0f s %4.2f cores  %s%s' % (x['estimate'], x['load'], x['target'], '  (alone)' if x['target'] in RUN_ALONE else
                                     '  (heavy)' if x['target'] in HEAVY else ''))
        return 0

    log_dir = tempfile.mkdtemp(prefix='test_pool_')
    running = {}   # pid -> (item, proc, log, start, cpu before)
    done = []
    failed = []
    start_all = time.monotonic()
    while todo or running:
        busy_ports = set().union(*[r[0]['ports'] for r in running.values()])
        alone_running = any(r[0]['alone'] for r in running.values())
        busy_cores = sum(r[0]['load'] for r in running.values())
        started = False
        for x in list(todo):
            if len(running) >= args.jobs or alone_running:
                break
            if x['alone'] and running:
                break  # wait until the pool drains, then it runs by itself
            if x['ports'] & busy_ports:
                continue
            if running and busy_cores + x['load'] > args.budget:
                continue
            proc, log, t0 = run(x['target'], log_dir)
            running[proc.pid] = (x, proc, log, t0)
            todo.remove(x)
            started = True
            alone_running = x['alone']
            busy_cores += x['load']
            busy_ports |= x['ports']
        if not running:
            if todo and not started:
                sys.exit('test_pool: nothing can start: %s' % [x['target'] for x in todo])
            continue
        pid, status, usage = os.wait4(-1, 0)
        if pid not in running:
            continue
        x, proc, log, t0 = running.pop(pid)
        wall = time.monotonic() - t0
        cpu = usage.ru_utime + usage.ru_stime
        rc = os.waitstatus_to_exitcode(status)
        bad = rc != 0 or result_failed(x['target'], x['file'])
        done.append((x['target'], wall, cpu, bad))
        print('%-8s %6.1f s wall %6.1f s CPU  %s' % ('FAILED' if bad else 'ok', wall, cpu, x['target']), flush=True)
        if bad:
            failed.append(x['target'])
            with open(log) as f:
                lines = [l for l in f if not re.match(r'^(-- |\[ *\d+%\]|Scanning|Built target|make\[\d\]: )', l)]
            sys.stdout.write(''.join(lines[-200:]))
            sys.stdout.flush()
    total = time.monotonic() - start_all
    history.update({t: {'wall_s': round(w, 1), 'cpu_s': round(c, 1)} for t, w, c, bad in done if not bad})
    with open(DURATIONS, 'w') as f:
        json.dump(history, f, indent=1, sort_keys=True)
    cpu = sum(c for _, _, c, _ in done)
    print('test_pool: %d targets in %.0f s on %d slots within %.2f cores (%.0f s of test wall time, %.0f CPU s); '
          '%d failed' % (len(done), total, args.jobs, args.budget, sum(w for _, w, _, _ in done), cpu, len(failed)))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
