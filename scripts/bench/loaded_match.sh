#!/usr/bin/env bash
# Timing on a loaded computer: a 2009 match at real_time_factor 1 while `stress-ng --cpu N`
# loads every core at normal priority (scripts/bench/loaded_match_bench.py). The bus loops, the
# device loops and the emulators run in SCHED_FIFO (hcl/, hal/, sim/realtime_priority); the
# brain, the recorder and the simulator's world do not. Targets: localization never lost nor
# stale, no board or device ERROR. Run from the repo root with the workspace sourced. ~2 min.
# Ends with: loaded_match lost_s L pose_gap_max_s G errors E factor_reached F stress cpuN
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export PATH=/usr/bin:/bin:$PATH
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$root/scripts/bench/loaded_match_bench.py" "$tmp/match" "$@"
