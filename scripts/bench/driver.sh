#!/usr/bin/env bash
# Driver benchmark: 20 fixed goto goals chained across the table with the product's Autopilot,
# limiter and the 2009 robot's curves and limits at 50 Hz: mean time to goal, final position
# and heading error, overshoot, and the cancel -> wheels-stopped time (p50/p99).
# Runs on the KINEMATIC MODEL (hal_nodes/driver/kinematic_model.h: one period of command delay
# and a first-order motor lag; the 2009 simulator's motor time constant is 0.06 s), and says
# so in its output: the full simulated stack (simulator + CAN emulators + HCL + HAL + MCL) was
# not available to the driver area when this was written.
# Run from the repo root with the workspace sourced. Prints figures, exits 0.
set -uo pipefail
bin=$(catkin_find --first-only hal_nodes driver_bench 2>/dev/null || true)
if [ -z "$bin" ] || [ ! -x "$bin" ]; then
  echo "driver bench: driver_bench not built (catkin_make first)"
  exit 1
fi
"$bin" --rate 50 --delay 1 --lag 0.02
echo "-- same, with the 2009 simulator's motor time constant (0.06 s) and two periods of delay:"
"$bin" --rate 50 --delay 2 --lag 0.06
