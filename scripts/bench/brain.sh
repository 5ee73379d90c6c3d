#!/usr/bin/env bash
# Brain benchmark: the latency from an opponent entering the opponent_ahead trigger's range
# to zero speed commanded on /hal/drive/cmd_vel (p50/p99), and the brain node's CPU use.
# Runs the real brain node (strategy brain_bench_idle from test/scripts, triggers from
# config/eurobot2009.yaml) on a private ROS master; the bench plays the front ranger
# (sensor_msgs/Range on /hal/rangers/sharp_front_left) and /odom (driving forwards: the trigger
# watches only a robot that drives). It measures the brain's share only: the
# simulator's ground truth -> motor board emulator path needs the full simulated robot.
# Run from the repo root with the workspace sourced. Prints figures; exits 1 when it could not measure.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
port=11471   # private master for this bench (brain area)
export ROS_MASTER_URI=http://127.0.0.1:$port
export PYTHONPATH=$root/test/scripts:${PYTHONPATH:-}
log=$(mktemp -d /tmp/bench_brain.XXXX)
roscore -p $port >"$log/roscore.log" 2>&1 &
core=$!
cleanup() { [ -n "${brain:-}" ] && kill "$brain" 2>/dev/null; kill "$core" 2>/dev/null; wait 2>/dev/null; rm -rf "$log"; }
trap cleanup EXIT
for _ in $(seq 50); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
rosparam load "$root/config/eurobot2009.yaml" >/dev/null
rosparam set /brain/strategy brain_bench_idle
rosparam set /brain/strategy_modules "[test_brain_strategies]"
rosparam set /brain/match/start immediate
rosparam set /brain/match/duration 1000
rosparam set /brain/triggers "{opponent_ahead: {rangers: [sharp_front_left], distance: 0.25, max_age: 0.5, holdoff: 0.2, clear_time: 0.1, max_wait: 5.0}}"
rosrun smart_brain brain >"$log/brain.log" 2>&1 &
brain=$!
python3 - "$brain" <<'PY'
import os, sys, threading, time
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Range

pid = int(sys.argv[1])
rospy.init_node('bench_brain', disable_signals=True)
zero = threading.Event()
def on_twist(m):
    if m.linear.x == 0.0 and m.angular.z == 0.0:
        zero.set()
rospy.Subscriber('/hal/drive/cmd_vel', Twist, on_twist, queue_size=10, tcp_nodelay=True)
pub = rospy.Publisher('/hal/rangers/sharp_front_left', Range, queue_size=1)
# The trigger fires only while the robot drives (/odom forward): it drives at 0.3 m/s throughout.
odom = rospy.Publisher('/odom', Odometry, queue_size=1, latch=True)
driving = Odometry()
driving.twist.twist.linear.x = 0.3

def rng(r):
    m = Range(radiation_type=Range.ULTRASOUND, field_of_view=0.5, min_range=0.03, max_range=2.5, range=r)
    m.header.stamp = rospy.Time.now()
    m.header.frame_id = 'front_left_ranger'
    return m

def cpu():
    with open('/proc/%d/stat' % pid) as f:
        fields = f.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')

deadline = time.time() + 30
while (pub.get_num_connections() == 0 or odom.get_num_connections() == 0) and time.time() < deadline:
    time.sleep(0.1)
odom.publish(driving)
time.sleep(1.0)
# CPU while idle-running (10 Hz loop, triggers polled at 50 Hz, far ranger at 20 Hz).
c0, t0 = cpu(), time.time()
end = t0 + 5.0
while time.time() < end:
    pub.publish(rng(1.5)); time.sleep(0.05)
idle_cpu = 100.0 * (cpu() - c0) / (time.time() - t0)
lat = []
c0, t0 = cpu(), time.time()
for i in range(60):
    for _ in range(10):         # clear for 0.5 s at 20 Hz: handler resumes, holdoff passes
        pub.publish(rng(1.5)); time.sleep(0.05)
    zero.clear()
    t = time.monotonic()
    pub.publish(rng(0.15))      # the opponent enters the range
    if zero.wait(1.0):
        lat.append(time.monotonic() - t)
    for _ in range(2):
        pub.publish(rng(0.15)); time.sleep(0.05)
busy_cpu = 100.0 * (cpu() - c0) / (time.time() - t0)
lat.sort()
if not lat:
    print('brain: no zero speed seen: FAILED to measure')
    sys.exit(1)
p = lambda q: lat[min(len(lat) - 1, int(q * len(lat)))] * 1000
print('brain: opponent in range -> zero speed on /hal/drive/cmd_vel (brain share, %d/60 events): p50 %.1f ms, p99 %.1f ms, max %.1f ms'
      % (len(lat), p(0.5), p(0.99), lat[-1] * 1000))
print('brain: CPU of the brain node: %.1f %% of one core idle-running, %.1f %% while the trigger fires every 0.6 s'
      % (idle_cpu, busy_cpu))
print('brain: not measured here: simulator ground truth -> motor board emulator zero speed (needs the simulated robot stack)')
PY
# a bench that could not measure says so to make bench (run_bench.sh reports it FAILED)
