#!/usr/bin/env bash
# Latency bench: one ranger reading followed through every hop of the whole simulated 2009
# robot, from the CAN frame that carries it to the CAN frame that stops the motors, for the
# brain's opponent_ahead trigger (reflex) and the driver's own avoidance (a second run, the
# brain's trigger out of reach); and the age of /mcl/pose when it arrives.
# scripts/bench/latency.launch at real time, measured by scripts/bench/latency_bench.py on a
# private ROS master. About 3 minutes.
# Usage: scripts/bench/latency.sh [--stress] [EVENTS per path, default 20]. Run from the repo root
# with the workspace sourced. --stress: the same while `stress-ng --cpu N` loads every core at
# normal priority (targets then: reflex p99 < 30 ms). Ends with:
#   reflex_p50_ms A reflex_p99_ms B avoid_p99_ms C pose_age_p99_ms D stress none|cpuN
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
port=11498   # private master for this bench
export ROS_MASTER_URI=http://127.0.0.1:$port
export PYTHONPATH=$root/test/scripts:${PYTHONPATH:-}
log=$(mktemp -d /tmp/bench_latency.XXXX)
export ROS_LOG_DIR=$log
launch=
stress=
stress_pid=
if [ "${1:-}" = "--stress" ]; then
  shift
  command -v stress-ng >/dev/null || { echo "latency --stress: stress-ng is not installed (make deps installs it)"; exit 2; }
  stress=cpu$(nproc)
fi
cleanup() {
  [ -n "$launch" ] && kill -INT "$launch" 2>/dev/null
  [ -n "$stress_pid" ] && kill -INT "$stress_pid" 2>/dev/null
  wait 2>/dev/null; rm -rf "$log"
}
trap cleanup EXIT
status=0
run() {  # run MODE BRAIN_TRIGGER
  roslaunch -p $port "$root/scripts/bench/latency.launch" brain_trigger:=$2 >"$log/launch_$1.log" 2>&1 &
  launch=$!
  for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
  if ! kill -0 "$launch" 2>/dev/null; then  # a refused config ends the launch at once: say so, do not wait on it
    echo "latency bench ($1) FAILED: the launch ended before the robot came up; launch log tail:"
    tail -20 "$log/launch_$1.log"
    status=1; launch=
    return
  fi
  if [ -n "$stress" ]; then  # the load starts once the robot is up: the bench measures a loaded robot, not a slow start
    stress-ng --cpu "$(nproc)" --quiet &
    stress_pid=$!
  fi
  if ! python3 "$root/scripts/bench/latency_bench.py" "$1" "${EVENTS}" | tee "$log/$1.out"; then
    echo "latency bench ($1) FAILED; launch log tail:"
    tail -20 "$log/launch_$1.log"
    status=1
  fi
  if [ -n "$stress_pid" ]; then kill -INT "$stress_pid" 2>/dev/null; wait "$stress_pid" 2>/dev/null; stress_pid=; fi
  kill -INT "$launch" 2>/dev/null; wait "$launch" 2>/dev/null
  launch=
}
EVENTS=${1:-20}
run reflex true
run avoid false
figure() { awk -v k="$1" '$1 == "figures" { for (i = 2; i < NF; i += 2) if ($i == k) v = $(i + 1) } END { print (v == "" ? "nan" : v) }' "$log"/*.out; }
echo "reflex_p50_ms $(figure reflex_p50_ms) reflex_p99_ms $(figure reflex_p99_ms) avoid_p99_ms $(figure avoid_p99_ms) pose_age_p99_ms $(figure pose_age_p99_ms) stress ${stress:-none}"
exit $status
