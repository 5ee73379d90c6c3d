#!/usr/bin/env python3
"""Screenshot of rviz with the Match panel during a running simulated 2009 match (the README's
docs/images/rviz_match_panel.png): the simulated robot headless, the cord pulled, then rviz on
a private Xvfb display with the shipped config, `import -window root` after a few seconds of play.

    python3 scripts/rviz_match_panel_screenshot.py [OUTPUT.png] [--seconds 12]

Runs on a master and channels of its own (port 11391, CAN udp 27072, camera 27272), so it can
run beside another simulation. Needs the workspace sourced and match_panel built."""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MASTER_PORT = 11391


def free_display():
    for n in range(300 + os.getpid() % 50, 400):
        if not os.path.exists('/tmp/.X%d-lock' % n) and not os.path.exists('/tmp/.X11-unix/X%d' % n):
            return n
    raise RuntimeError('no free X display number')


def stop(proc):
    if proc is None or proc.poll() is not None:
        return
    os.killpg(proc.pid, signal.SIGINT)  # roslaunch shuts its nodes down on SIGINT
    try:
        proc.wait(timeout=20)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('output', nargs='?', default=os.path.join(ROOT, 'docs', 'images', 'rviz_match_panel.png'))
    parser.add_argument('--seconds', type=float, default=12.0, help='of play before the screenshot')
    args = parser.parse_args()

    os.environ['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % MASTER_PORT
    import rospy  # after ROS_MASTER_URI: rospy reads it at import
    from robot_sim.srv import SetSwitch
    from smart_brain.msg import MatchStatus

    tmp = tempfile.mkdtemp(prefix='rviz_match_panel_')
    launch = rviz = None
    try:
        launch = subprocess.Popen(
            ['roslaunch', '-p', str(MASTER_PORT), os.path.join(ROOT, 'launch', 'eurobot2009.launch'), 'rviz:=false',
             'can_bus:=udp://127.0.0.1:27072', 'sim_dir:=%s/sim' % tmp, 'camera_port:=27272'],
            stdout=open(os.path.join(tmp, 'launch.log'), 'w'), stderr=subprocess.STDOUT, start_new_session=True)
        time.sleep(3.0)
        rospy.init_node('rviz_match_panel_screenshot', anonymous=True, disable_signals=True)
        status = {}
        rospy.Subscriber('/brain/match_status', MatchStatus, lambda m: status.update(last=m))
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not (status.get('last') and status['last'].ready):
            time.sleep(0.5)
        if not status.get('last') or not status['last'].ready:
            sys.exit('the brain never got ready: %s (see %s/launch.log)' % (status.get('last'), tmp))

        display = free_display()
        env = dict(os.environ, XAUTHORITY=os.path.join(tmp, 'Xauthority'))
        rviz = subprocess.Popen(
            ['xvfb-run', '-n', str(display), '-f', env['XAUTHORITY'], '-s', '-screen 0 1024x768x24', 'rviz', '-d',
             os.path.join(ROOT, 'robot_description', 'rviz', 'eurobot2009.rviz')],
            env=env, stdout=open(os.path.join(tmp, 'rviz.log'), 'w'), stderr=subprocess.STDOUT, start_new_session=True)
        time.sleep(8.0)  # rviz loads its config and the panel asks for the strategy list

        rospy.wait_for_service('/sim/set_switch', 10.0)
        res = rospy.ServiceProxy('/sim/set_switch', SetSwitch)('start_cord', False)
        if not res.ok:
            sys.exit('the cord did not pull: %s' % res.message)
        time.sleep(args.seconds)
        if status['last'].state != 'running':
            sys.exit('the match is not running: %s' % status['last'])
        env['DISPLAY'] = ':%d' % display
        subprocess.run(['import', '-window', 'root', args.output], env=env, check=True, timeout=30)
        print('screenshot: %s (match %s, %.1f s left)' % (args.output, status['last'].state, status['last'].remaining))
    finally:
        stop(rviz)
        stop(launch)
        rviz_log = os.path.join(tmp, 'rviz.log')
        if os.path.exists(rviz_log):  # a panel rviz could not load says so only here
            for line in open(rviz_log, errors='replace'):
                if 'ERROR' in line or 'rror' in line:
                    print('rviz: ' + line.rstrip())
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == '__main__':
    main()
