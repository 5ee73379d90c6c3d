"""`make run`: one simulated match of a robot, headless, from start cord to report.

    scripts/run_match.py ROBOT [--out DIR] [--strategy NAME] [--seed N] [--real-time-factor F]
                         [--overlay PARAMS.yaml] [--faults SCHEDULE.yaml] [--side ZONE]

Starts launch/ROBOT.launch (simulator, HCL, HAL, brain) with record:=true, waits until the
brain says the robot is ready (every product node runs, every board and device OK: the "ready:
pull cord" a team member reads on the LCD; until then it prints what is not ready) and the robot
shows the cord inserted (HAL human interface, /hal/hmi/input), pulls the start cord
(the simulated cord switch, read by the boards, the HMI device and the brain), follows the
match clock, stops everything once the brain reports the match ended, and writes the match
report. Prints where the bag and the report are and the referee's score. Robots without a
match (no table in their config: the skeleton) just run. With --side, the robot plays from that
start zone: its start, initial_pose, side switch and the opponent's start follow it (OUT/side.yaml,
robot_core.start_zone.side_overlay, over the other overlays). With --faults, the schedule's faults are injected into the match at
their match times (robot_tools.chaos.injector: `make chaos`), and what was injected when is
written to OUT/faults.yaml. A recorder that was killed and respawned left parts of the bag:
they are joined into the one bag (robot_tools.bag_parts) before the report.

A robot whose launch has `can_bus`, `camera_port` or `sim_dir` arguments gets channels of its
own (free ports, a fresh directory): two simulations on one CAN bus answer each other's drivers
(a second simulated robot on the machine, e.g. a test, can make the start cord read open), and a
taken camera port stops the simulator.
"""
import argparse
import os
import random
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

import yaml

from robot_tools.paths import ROOT, SCRIPTS


def log(msg):
    print('run: ' + msg, flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('robot')
    ap.add_argument('--out', default=None,
                    help='where the bag and report go (default: a new report/ROBOT/<UTC time>_seed<k>/, and '
                         'report/ROBOT/latest pointing to it once the match is complete)')
    ap.add_argument('--strategy', default=None)
    ap.add_argument('--seed', default='1')
    ap.add_argument('--real-time-factor', default='1.0', help='simulated seconds per wall second')
    ap.add_argument('--overlay', default=None,
                    help='YAML of parameters loaded after the config (the launch argument overlay), '
                         'e.g. another opponent: sim: {world: {opponent: {...}}}; several, comma-separated, '
                         'each over the one before')
    ap.add_argument('--faults', default=None, help='YAML list of faults to inject (robot_tools.chaos.injector)')
    ap.add_argument('--side', default=None, help='the start zone to play from (its name: the colour); default: '
                    'where the config starts the simulated robot')
    ap.add_argument('--startup-timeout', type=float, default=120.0, help='[s, wall] to reach waiting_for_start')
    ap.add_argument('--match-timeout', type=float, default=400.0, help='[s, wall] for the match to end')
    args = ap.parse_args()

    launch = os.path.join(ROOT, 'launch', args.robot + '.launch')
    if not os.path.exists(launch):
        robots = sorted(f[:-7] for f in os.listdir(os.path.join(ROOT, 'launch')) if f.endswith('.launch')
                        and f != 'replay.launch')
        sys.exit('run: ROBOT=%s: no launch/%s.launch; allowed values: %s' % (args.robot, args.robot, ', '.join(robots)))
    with open(os.path.join(ROOT, 'config', args.robot + '.yaml')) as f:
        plays_matches = 'table' in (yaml.safe_load(f) or {})
    if not plays_matches:  # a robot on a desk (the skeleton and its copies): no match to play
        log('starting %s (no table in its config: no match to play); Ctrl-C to stop' % args.robot)
        os.execvp('roslaunch', ['roslaunch', launch])

    from robot_tools import bag_parts
    from robot_tools.matches import run_folders
    own_folder = args.out is None  # `make run`: a folder of its own, `latest` once complete
    if own_folder:
        args.out = run_folders.new_folder(os.path.join(ROOT, 'report', args.robot),
                                          '%s_seed%s' % (run_folders.stamp(), args.seed))
    os.makedirs(args.out, exist_ok=True)
    log('this run\'s folder: %s' % args.out)
    bag = os.path.join(args.out, args.robot + '_match.bag')
    png = os.path.join(args.out, args.robot + '_match.png')
    for stale in [bag, bag + '.active'] + bag_parts.parts(bag):
        if os.path.exists(stale):
            os.remove(stale)
    cmd = ['roslaunch', launch, 'record:=true', 'bag:=' + bag, 'seed:=' + args.seed,
           'real_time_factor:=' + args.real_time_factor]
    # Channels of its own, so a simulation already running here (a test) cannot answer this
    # robot's drivers nor hold its ports.
    declared = open(launch).read()
    sim_dir = None
    if 'name="can_bus"' in declared:
        cmd.append('can_bus:=udp://127.0.0.1:%d' % free_port(socket.SOCK_DGRAM))
    if 'name="camera_port"' in declared:
        cmd.append('camera_port:=%d' % free_port(socket.SOCK_STREAM))
    if 'name="sim_dir"' in declared:
        sim_dir = tempfile.mkdtemp(prefix='robot_sim_%s_' % args.robot)
        cmd.append('sim_dir:=' + sim_dir)
    if args.strategy:
        cmd.append('strategy:=' + args.strategy)
    if args.side:  # the side's overlay, kept beside the bag, over the user's
        from robot_tools.matches.match_config import side_overlay_file
        args.overlay = ','.join(p for p in (args.overlay, side_overlay_file(args.robot, args.overlay, args.side,
                                                                              args.out, 'run')) if p)
    if args.overlay:
        if 'name="overlay"' not in declared:
            sys.exit('run: launch/%s.launch has no overlay argument' % args.robot)
        overlay = os.path.abspath(args.overlay)
        if ',' in args.overlay:  # the launch loads one file: the several merged, kept beside the bag
            overlay = os.path.join(os.path.abspath(args.out), 'overlays_merged.yaml')
            with open(overlay, 'w') as f:
                f.write('# scripts/run_match.py: --overlay %s, merged in that order\n' % args.overlay)
                from robot_tools.matches.match_config import user_overlay
                yaml.safe_dump(user_overlay(args.overlay, 'run'), f, default_flow_style=False)
        cmd.append('overlay:=' + overlay)
    log('starting the simulated %s robot headless: %s' % (args.robot, ' '.join(cmd[2:])))
    launch_log = open(os.path.join(args.out, args.robot + '_launch.log'), 'w')
    proc = subprocess.Popen(cmd, stdout=launch_log, stderr=subprocess.STDOUT, preexec_fn=own_session_dying_with_parent)
    ended = False
    try:
        ended = follow_match(args, proc, launch_log.name)
    except BaseException as e:  # Ctrl-C, a timeout: what was written stays, marked
        run_folders.mark_incomplete(args.out, 'interrupted: %s' % (type(e).__name__ if not str(e) else e))
        raise
    finally:
        log('stopping the robot')
        signal_group(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            signal_group(proc.pid, signal.SIGKILL)
        if sim_dir:
            shutil.rmtree(sim_dir, ignore_errors=True)
    log('launch output: %s' % launch_log.name)
    joined = bag_parts.join(bag)
    if joined:
        log('the recorder was restarted during the match: %s' % joined)
    if not os.path.exists(bag):
        run_folders.mark_incomplete(args.out, 'no bag was written: the match never started (see %s)' % launch_log.name)
        sys.exit('run: no bag was written (%s); see the launch output' % bag)
    log('writing the match report')
    rc = subprocess.call([sys.executable, os.path.join(ROOT, 'scripts', 'match_report.py'), bag, '-o', png])
    log('bag: %s' % bag)
    if rc == 0:
        log('report: %s' % png)
    if ended and rc == 0:
        if own_folder:
            log('latest: %s' % run_folders.mark_complete(args.out))
        return 0
    run_folders.mark_incomplete(args.out, 'the match did not end as it should (see run: lines above and %s)'
                                % launch_log.name if not ended else 'the match report failed')
    return 1


def die_with_parent():
    """In a child, before exec: SIGINT when the process that started it dies (prctl
    PR_SET_PDEATHSIG). A runner killed -9 (a Dask worker lost mid-match) would otherwise leave
    its simulation running at full speed; roslaunch and run_match.py stop cleanly on SIGINT."""
    import ctypes
    ctypes.CDLL('libc.so.6', use_errno=True).prctl(1, signal.SIGINT)  # 1: PR_SET_PDEATHSIG


def own_session_dying_with_parent():
    os.setsid()  # the launch's whole process group is stopped at the end (killpg)
    die_with_parent()


def signal_group(pid, sig):
    """Signals the launch's process group; a launch that already ended (a refused config) has none."""
    try:
        os.killpg(pid, sig)
    except ProcessLookupError:
        pass


def free_port(kind):
    """A UDP or TCP port on loopback nobody holds now (this run's emulators bind it), from the
    project's 28000-28999: below the ephemeral range, so no outgoing connection takes it
    between this check and the emulator's bind (see docs/getting-started.md, launch arguments)."""
    for port in random.sample(range(28000, 29000), 1000):
        s = socket.socket(socket.AF_INET, kind)
        try:
            s.bind(('127.0.0.1', port))
            return port
        except OSError:
            continue
        finally:
            s.close()
    raise RuntimeError('no free port in 28000-28999 on 127.0.0.1')


def launch_ended(proc, launch_log):
    """None while the launch runs; else why it ended: its FATAL lines and dead required nodes."""
    if proc.poll() is None:
        return None
    with open(launch_log, errors='replace') as f:
        lines = [l.strip() for l in f if '[FATAL]' in l or 'REQUIRED process' in l or l.startswith('config error:')]
    return '; '.join(lines[-4:]) or 'exit code %s' % proc.returncode


def follow_match(args, proc, launch_log):
    import rospy
    deadline = time.monotonic() + args.startup_timeout
    while True:  # roslaunch brings the master up
        why = launch_ended(proc, launch_log)
        if why:
            log('not ready: the launch ended before the match: %s' % why)
            return False
        try:
            # Not before the launch has set /use_sim_time: rospy reads it once, at init, and
            # would otherwise keep the wall clock (the fault schedule is in simulated time).
            import rosgraph
            if not rosgraph.Master('/run_match').hasParam('/use_sim_time'):
                raise RuntimeError('the launch has not set its parameters yet')
            rospy.init_node('run_match', anonymous=True, disable_signals=True)
            break
        except Exception:
            if time.monotonic() > deadline:
                raise SystemExit('run: no ROS master after %.0f s' % args.startup_timeout)
            time.sleep(1.0)
    from smart_brain.msg import MatchStatus
    status = {'msg': None}
    rospy.Subscriber('/brain/match_status', MatchStatus, lambda m: status.__setitem__('msg', m), queue_size=1)

    def state():
        return status['msg'].state if status['msg'] else None

    said = None
    while not (state() == 'waiting_for_start' and status['msg'].ready):
        why = launch_ended(proc, launch_log)
        if why:
            log('not ready: the launch ended before the match: %s' % why)
            return False
        readiness = status['msg'].readiness if status['msg'] else 'not ready: the brain has not reported yet'
        if re.sub(r'[0-9.]+', '', readiness) != said:  # what changed, not a figure
            log(readiness if len(readiness) < 400 else readiness[:400] + ' ...')
            said = re.sub(r'[0-9.]+', '', readiness)
        if time.monotonic() > deadline:
            log('the robot never became ready in %.0f s (brain: %s, %s); see the launch output'
                % (args.startup_timeout, state(), readiness))
            return False
        time.sleep(0.5)
    # A team member pulls the cord once the robot shows it inserted: before that the human
    # interface has not armed (it never saw the cord in) and pulling it starts nothing.
    from hal_nodes.msg import HumanInput
    hmi = {'msg': None}
    rospy.Subscriber('/hal/hmi/input', HumanInput, lambda m: hmi.__setitem__('msg', m), queue_size=1)
    cord_deadline = time.monotonic() + 30.0
    while not (hmi['msg'] and hmi['msg'].cord_inserted) and time.monotonic() < cord_deadline:
        time.sleep(0.1)
    if not (hmi['msg'] and hmi['msg'].cord_inserted):
        log('WARNING: the robot never showed the start cord inserted (/hal/hmi/input: %s)' %
            ('nothing' if hmi['msg'] is None else 'cord_inserted false'))
    log('ready (strategy %s), cord inserted; pulling the start cord' % status['msg'].strategy)
    from robot_sim.srv import SetSwitch
    rospy.wait_for_service('/sim/set_switch', timeout=30)
    rospy.ServiceProxy('/sim/set_switch', SetSwitch)(name='start_cord', closed=False)
    cord_deadline = time.monotonic() + 10.0
    while state() == 'waiting_for_start' and time.monotonic() < cord_deadline:
        time.sleep(0.2)
    if state() == 'waiting_for_start':
        # Should not happen: the cord path (world, servo/io board emulator, driver, HMI device,
        # brain) is broken. Keep the match going and say so.
        log('WARNING: the start cord did not start the match within 10 s; starting it through /brain/start')
        from std_srvs.srv import Trigger
        rospy.wait_for_service('/brain/start', timeout=10)
        rospy.ServiceProxy('/brain/start', Trigger)()
    injector = None
    if args.faults:
        import yaml
        from robot_tools.chaos.injector import FaultInjector
        while state() == 'waiting_for_start':
            time.sleep(0.01)
        m = status['msg']
        with open(args.faults) as f:
            faults = yaml.safe_load(f) or []
        injector = FaultInjector(faults, os.path.join(args.out, 'faults.yaml'), m.header.stamp.to_sec() - m.elapsed)
        injector.start()
        log('%d fault(s) scheduled (%s)' % (len(faults), args.faults))
    deadline = time.monotonic() + args.match_timeout
    last = -10.0
    while state() != 'ended':
        why = launch_ended(proc, launch_log)
        if why:
            log('the launch ended during the match: %s' % why)
            return False
        if time.monotonic() > deadline:
            log('the match did not end within %.0f s' % args.match_timeout)
            return False
        m = status['msg']
        if m and m.elapsed - last >= 10.0:
            last = m.elapsed
            log('match %s: %.0f s elapsed, %.0f s left' % (m.state, m.elapsed, m.remaining))
        time.sleep(0.5)
    log('match ended; effectors deactivated: %s' % status['msg'].effectors_deactivated)
    if injector:
        injector.wait(30.0)
        log('faults: %s' % ', '.join('%s %s at %.1f s: %s' % (d['kind'], d.get('target', ''), d['start'] - injector.t0,
                                                              d['outcome']) for d in injector.done))
    try:
        from robot_sim.msg import MatchState
        referee = rospy.wait_for_message('/sim/match', MatchState, timeout=5.0)
        log('referee (simulator, %s rules, we play %s): score: ours %d, opponent %d'
            % (referee.year, referee.colour_ours or '?', referee.score_ours, referee.score_opponent))
    except Exception as e:  # the report reads the score from the bag as well
        log('no referee score on /sim/match: %s' % e)
    # Let the recorder take 1.5 simulated seconds past the end (the report checks the effectors 1 s
    # after it), bounded in wall time should the clock stop.
    until, deadline = rospy.get_time() + 1.5, time.monotonic() + 5.0
    while rospy.get_time() < until and time.monotonic() < deadline:
        time.sleep(0.05)
    return True


if __name__ == '__main__':
    sys.exit(main())


def run_one(robot, seed, factor, folder, overlay, strategy, index, n, extra=()):
    """scripts/run_match.py on a ROS master of its own (each run starts and stops its master; two
    in a row on one port, or on a test's master, would share parameters and latched topics).
    Its `run:` lines are shown, its whole output kept in the folder. Returns its exit code."""
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % free_port(socket.SOCK_STREAM))
    cmd = [sys.executable, os.path.join(SCRIPTS, 'run_match.py'), robot, '--out', folder, '--seed', str(seed),
           '--real-time-factor', '%g' % factor, '--overlay', overlay]
    if strategy:
        cmd += ['--strategy', strategy]
    cmd += list(extra)
    with open(os.path.join(folder, 'run_match.out'), 'w') as out:
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                universal_newlines=True, errors='replace', preexec_fn=die_with_parent)
        try:
            for line in proc.stdout:
                out.write(line)
                if line.startswith('run: '):  # the report's summary stays in the folder's .txt
                    print('  [%d/%d] %s' % (index, n, line.rstrip()), flush=True)
        except KeyboardInterrupt:
            # run_match.py got the Ctrl-C too and stops its robot, printing as it goes: keep its
            # pipe open until it is done, or it dies on the closed pipe and leaves the robot running.
            out.write(proc.stdout.read())
            proc.wait()
            raise
        return proc.wait()

