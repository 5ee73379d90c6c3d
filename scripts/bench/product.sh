#!/usr/bin/env bash
# Product benchmarks: what recording, replay and the match report cost.
# Prints: bag size per match minute of the skeleton robot; how much faster than real time a
# bag replays through HAL with HAL still seeing every board state; match report time for a
# 100 s bag. Runs from the repo root with the workspace sourced; own master on port 11731.
set -uo pipefail
set -m   # background jobs keep SIGINT (roslaunch stops cleanly, the bag gets closed)
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d /tmp/bench_product.XXXXXX)
export ROS_MASTER_URI=http://localhost:11731
cleanup() { [ -n "${core:-}" ] && kill -INT "$core" 2>/dev/null; wait 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
roscore -p 11731 >"$tmp/core.log" 2>&1 & core=$!
sleep 3

# 1. Record 20 s of the skeleton robot.
roslaunch "$root/launch/skeleton.launch" record:=true bag:="$tmp/match.bag" >"$tmp/rec.log" 2>&1 & rec=$!
sleep 22; kill -INT $rec; wait $rec 2>/dev/null
python3 - "$tmp/match.bag" <<'PY'
import os, sys, rosbag
b = rosbag.Bag(sys.argv[1]); d = b.get_end_time() - b.get_start_time()
n = sum(i.message_count for i in b.get_type_and_topic_info().topics.values())
print('product: skeleton bag %.1f s, %d messages, %.2f MB per match minute' % (d, n, os.path.getsize(sys.argv[1]) / 1e6 / d * 60))
PY

# 2. Replay through HAL at increasing rates: readings per recorded board state.
for rate in 1 4 16; do
  rosparam delete /use_sim_time >/dev/null 2>&1
  ( rostopic echo -p /hal/example_device/reading > "$tmp/replay_$rate.csv" 2>/dev/null & echo $! > "$tmp/echo.pid"; wait ) &
  t0=$(date +%s.%N)
  roslaunch "$root/launch/replay.launch" bag:="$tmp/match.bag" robot:=skeleton sim:=true rviz:=false rate:=$rate >"$tmp/replay.log" 2>&1
  t1=$(date +%s.%N)
  kill "$(cat "$tmp/echo.pid")" 2>/dev/null; sleep 0.5
  python3 - "$tmp/match.bag" "$tmp/replay_$rate.csv" "$rate" "$t0" "$t1" <<'PY'
import sys, rosbag
bag, csv, rate, t0, t1 = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5])
rec = sum(1 for _ in rosbag.Bag(bag).read_messages(topics=['/hal/example_device/reading']))
got = max(0, sum(1 for _ in open(csv)) - 1)
print('product: replay at rate %sx: %.1f s wall, HAL readings %d of %d in the match (%.0f %%)' % (rate, t1 - t0, got, rec, 100.0 * got / max(rec, 1)))
PY
done

# 3. The match report of a synthetic 100 s bag (truth and estimate at 50 Hz, states, logs).
python3 - "$tmp/synthetic.bag" <<'PY'
import math, sys, rosbag, rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
with rosbag.Bag(sys.argv[1], 'w') as b:
    for i in range(5000):
        t = rospy.Time(10 + i * 0.02)
        o = Odometry(); o.header.stamp = t; o.pose.pose.position.x = 0.3 + i * 0.0005; o.pose.pose.position.y = 1 + 0.5 * math.sin(i / 500.); o.pose.pose.orientation.w = 1
        b.write('/sim/ground_truth', o, t)
        e = PoseWithCovarianceStamped(); e.header.stamp = t; e.pose.pose = o.pose.pose
        b.write('/mcl/pose', e, t)
PY
t0=$(date +%s.%N)
python3 "$root/scripts/match_report.py" "$tmp/synthetic.bag" -o "$tmp/synthetic.png" >/dev/null
t1=$(date +%s.%N)
python3 -c "print('product: match report of a 100 s bag (2 x 5000 poses): %.2f s' % ($t1 - $t0))"
exit 0
