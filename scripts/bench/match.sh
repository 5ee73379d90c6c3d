#!/usr/bin/env bash
# Benchmark of a whole simulated 2009 match (simulator, emulated boards, HCL, HAL, brain,
# recorder): its wall time as fast as the machine goes (real_time_factor 0) and the factor
# reached over the match, then each node's share of one core at factor 1 over 40 s of a match.
# Runs with the workspace sourced, from the repo root. ~3 min.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export PATH=/usr/bin:/bin:$PATH
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export ROS_MASTER_URI=http://localhost:$(python3 -c 'import random; print(random.randint(28000, 28999))')

echo "== a 2009 match as fast as the machine goes (real_time_factor 0)"
start=$(date +%s.%N)
python3 "$root/scripts/run_match.py" eurobot2009 --real-time-factor 0 --out "$tmp/f0" > "$tmp/f0.log" 2>&1 || true
end=$(date +%s.%N)
grep -E "referee|never|ended" "$tmp/f0.log" | sed 's/^/  /' || true
python3 - "$tmp/f0/eurobot2009_launch.log" "$start" "$end" <<'PY'
import sys
from robot_tools.matches.match_rows import match_span
log, start, end = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
begin, finish = match_span(log)  # the brain's match start and end, [wall, simulated]
if begin and finish:
    wall, sim = finish[0] - begin[0], finish[1] - begin[1]
    print('match_wall_s %.1f (start cord to match end, %.1f s simulated)' % (wall, sim))
    print('real_time_factor_reached %.2f' % (sim / wall))
print('run_wall_s %.1f (launch to report)' % (end - start))
PY

echo "== each node's share of one core at real_time_factor 1, 40 s of a match"
python3 "$root/scripts/bench/node_cpu.py" 40 --wait-topic /brain/match_status > "$tmp/cpu.txt" 2>&1 &
sampler=$!
python3 "$root/scripts/run_match.py" eurobot2009 --real-time-factor 1 --out "$tmp/f1" > "$tmp/f1.log" 2>&1 || true
wait $sampler || true
cat "$tmp/cpu.txt"
