#!/usr/bin/env bash
# Driver benchmark: 20 fixed goto goals chained across the table on the 2009 robot,
# mean time to goal, final position and heading error, overshoot, and the cancel -> wheels
# stopped time (p50/p99).
# 1. In the simulator (scripts/bench/driver_sim.launch: simulator, CAN emulators, HCL, HAL with
#    the localization and the driver; empty table, no opponent), measured against ground truth
#    by scripts/bench/driver_sim_bench.py on a private ROS master. About 4 minutes.
# 2. The same goals on the driver's kinematic model (hal_nodes/driver/kinematic_model.h: the
#    Autopilot and limiter alone, perfect localization): what the control curves do by themselves.
# Run from the repo root with the workspace sourced. Prints figures; exits 1 if the simulated
# run could not start.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
port=11497   # private master for this bench (driver area)
export ROS_MASTER_URI=http://127.0.0.1:$port
export PYTHONPATH=$root/test/scripts:${PYTHONPATH:-}
log=$(mktemp -d /tmp/bench_driver.XXXX)
export ROS_LOG_DIR=$log
roslaunch -p $port "$root/scripts/bench/driver_sim.launch" >"$log/launch.log" 2>&1 &
launch=$!
cleanup() { kill -INT "$launch" 2>/dev/null; wait "$launch" 2>/dev/null; rm -rf "$log"; }
trap cleanup EXIT
for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
echo "-- simulator (2009 robot, whole stack):"
status=0
if ! python3 "$root/scripts/bench/driver_sim_bench.py"; then
  echo "driver sim bench FAILED; launch log tail:"
  tail -20 "$log/launch.log"
  status=1
fi
kill -INT "$launch" 2>/dev/null; wait "$launch" 2>/dev/null
bin=$(catkin_find --first-only hal_nodes driver_bench 2>/dev/null || true)
if [ -z "$bin" ] || [ ! -x "$bin" ]; then
  echo "driver bench: driver_bench not built (catkin_make first)"
  exit 1
fi
# The control rate and the simulated drive motors' time constant, from the robot's config.
read -r rate lag < <(python3 -c "
import yaml
config = yaml.safe_load(open('$root/config/eurobot2009.yaml'))
sim = yaml.safe_load(open('$root/config/eurobot2009.sim.yaml'))
print(config['hal']['driver']['rate'], sim['sim']['world']['robot']['motors']['left']['time_constant'])")
echo "-- kinematic model (Autopilot + limiter at $rate Hz, one period of delay, 20 ms motor lag):"
"$bin" --rate "$rate" --delay 1 --lag 0.02
echo "-- same, with the 2009 simulator's motor time constant ($lag s) and two periods of delay:"
"$bin" --rate "$rate" --delay 2 --lag "$lag"
exit $status
