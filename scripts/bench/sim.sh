#!/usr/bin/env bash
# Benchmark of the simulated world (robot_sim): the real-time factor the world step reaches
# with our robot, the opponent, the game elements and every configured sensor read at its
# usual rate, for each robot's configuration. Target: >= 20x for the world step alone.
# Runs with the workspace sourced, from the repo root; needs no ROS master.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export PATH=/usr/bin:/bin:$PATH
bench=$(catkin_find --first-only robot_sim sim_bench 2>/dev/null || true)
[ -x "$bench" ] || bench=$(ls "$root"/devel*/lib/robot_sim/sim_bench 2>/dev/null | head -n1)
if [ ! -x "$bench" ]; then
  echo "sim bench: sim_bench not built (catkin_make first)"
  exit 0
fi
seconds=${SIM_BENCH_SECONDS:-200}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "== simulator world step (${seconds} s simulated per run, 1 core)"
for robot in eurobot2009 logion; do
  # The robot's parameter tree (base config + simulation overlay) as one XML-RPC value.
  python3 - "$root/config/$robot.yaml" "$root/config/$robot.sim.yaml" > "$tmp/$robot.xml" <<'PY'
import sys, xmlrpc.client, yaml
tree = {}
def merge(a, b):
    for k, v in b.items():
        if isinstance(v, dict) and isinstance(a.get(k), dict):
            merge(a[k], v)
        else:
            a[k] = v
for f in sys.argv[1:]:
    merge(tree, yaml.safe_load(open(f)) or {})
print(xmlrpc.client.dumps((tree,)))
PY
  echo "$robot (our robot + opponent):"
  "$bench" "$tmp/$robot.xml" "$seconds"
done
