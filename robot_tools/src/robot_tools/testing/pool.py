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
Called by run_tests.sh (scripts/test_pool.py) with the workspace sourced, once the test binaries are built.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

from robot_tools.paths import ROOT
from robot_tools.testing.channels import fixed_channels, robot_launches
from robot_tools.testing.targets import BUILD, package_dirs, result_failed, rostest_file, targets, time_limit

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


def admit(todo, running, jobs, budget):
    """The tests of `todo` (in its order) to start now beside the `running` ones: at most `jobs`
    at once, a test that runs alone only into an empty pool and nothing beside it, no two sharing
    a channel, and their loads within `budget` cores (a first test always starts)."""
    busy_ports = set().union(*[x['ports'] for x in running])
    alone = any(x['alone'] for x in running)
    busy_cores = sum(x['load'] for x in running)
    count = len(running)
    out = []
    for x in todo:
        if count >= jobs or alone:
            break
        if x['alone'] and count:
            break  # wait until the pool drains, then it runs by itself
        if x['ports'] & busy_ports:
            continue
        if count and busy_cores + x['load'] > budget:
            continue
        out.append(x)
        count += 1
        alone = x['alone']
        busy_cores += x['load']
        busy_ports |= x['ports']
    return out


def run(target, log_dir):
    """Starts one target; returns (process, log path, start time)."""
    log = os.path.join(log_dir, target + '.log')
    with open(log, 'w') as f:
        proc = subprocess.Popen(['make', '-C', BUILD, '-j1', target], stdout=f, stderr=subprocess.STDOUT,
                                cwd=ROOT)
    return proc, log, time.monotonic()


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
        starting = admit(todo, [r[0] for r in running.values()], args.jobs, args.budget)
        for x in starting:
            proc, log, t0 = run(x['target'], log_dir)
            running[proc.pid] = (x, proc, log, t0)
            todo.remove(x)
        started = bool(starting)
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
