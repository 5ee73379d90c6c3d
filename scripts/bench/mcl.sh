#!/usr/bin/env bash
# Localization: our MCL (mcl_bench, the node's filter library) side by side with
# MRPT's stock CMonteCarloLocalization2D + CBeaconMap (mcl_bench_stock) on the committed
# synthetic beacon runs of scripts/bench/data (generated into build/bench_data), both modes, 2,000 particles, and the ratios
# ours/stock. The stock filter gets the run's true range noise and an odometry model matched
# to the run (its defaults do worse). Its 10,000-particle global runs (README.md: 3.2 ms per
# update) are left out to keep `make bench` short: `rosrun hal_nodes mcl_bench_stock RUN 10000
# global --range-std 0.03` reproduces them. Wall-clock figures on this machine, shared cores.
# Then the localization in the whole simulator (the 2009 robot: emulated boards, HCL, HAL) on
# the fixed route of the mcl_sim_eurobot2009 rostest (two laps, beacon 2 silenced 10 s,
# ~global_localization, a kidnap), at each simulator seed of MCL_SIM_SEEDS (default 5; e.g.
# MCL_SIM_SEEDS="5 6 7" for several): errors
# against /sim/ground_truth at each estimate's stamp, the device's cost per step (sampled from
# /diagnostics), hal_node CPU (/proc/<pid>/stat over the route; every HAL device of the robot
# runs in that process, the localization's own share is cost per step x ~48 steps/s).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
# The two runs (scripts/bench/data/README.md), written by their deterministic generator: the same
# bytes on every machine, so only the generator is committed.
data="$root/build/bench_data"
mkdir -p "$data"
gen="$root/scripts/bench/data/make_beacon_run.py"
[ -f "$data/run_seed1.csv" ] || python3 "$gen" --seed 1 "$data/run_seed1.csv"
[ -f "$data/run_seed2_noisy.csv" ] || python3 "$gen" --seed 2 --range-std 0.02 --outlier 0.05 "$data/run_seed2_noisy.csv"
n=2000
ratio() {  # ours stock field -> ours/stock
  python3 - "$1" "$2" "$3" <<'PY'
import sys
def f(line, key):
    t = line.split(); return float(t[t.index(key) + 1])
o, s, k = sys.argv[1], sys.argv[2], sys.argv[3]
print(f"{f(o, k) / f(s, k):.2f}" if f(s, k) > 0 else "n/a")
PY
}
for run in "run_seed1.csv 0.01" "run_seed2_noisy.csv 0.02"; do
  set -- $run
  file="$data/$1"; noise=$2
  for mode in track global; do
    ours=$(rosrun hal_nodes mcl_bench "$file" $n $mode)
    stock=$(rosrun hal_nodes mcl_bench_stock "$file" $n $mode --range-std "$noise" --tuned-motion)
    echo "$1 ours : $ours"
    echo "$1 stock: $stock"
    echo "$1 $mode ratio ours/stock: p50_ms $(ratio "$ours" "$stock" p50_ms) rmse_mm $(ratio "$ours" "$stock" rmse_mm) max_mm $(ratio "$ours" "$stock" max_mm) heading_rmse_deg $(ratio "$ours" "$stock" heading_rmse_deg)"
  done
  # Ours with the KLD-adaptive count (the node's default: at most N particles, fewer when certain).
  echo "$1 ours (KLD, max $n): $(rosrun hal_nodes mcl_bench "$file" $n track --kld)"
done

for seed in ${MCL_SIM_SEEDS:-5}; do
  figures=$(mktemp)
  # MCL_SIM_CONFIG: another simulation overlay than config/eurobot2009.sim.yaml
  if rostest system_tests mcl_sim_eurobot2009.test seed:="$seed" figures:="$figures" ${MCL_SIM_CONFIG:+sim_config:="$MCL_SIM_CONFIG"} >"$figures.log" 2>&1; then
    verdict=passed
    rm -f "$figures.log"
  else
    verdict="FAILED (rostest log: $figures.log)"
  fi
  echo "simulator seed $seed (mcl_sim_eurobot2009 rostest $verdict):"
  sed 's/^/  /' "$figures"
  rm -f "$figures"
done
