#!/usr/bin/env bash
# Loop scheduler: achieved rate and period jitter of one board loop at 100 Hz and 1 kHz
# (wall time, this machine), via the hcl_drivers loop_bench tool.
set -euo pipefail
rosrun hcl_drivers loop_bench 100 3
rosrun hcl_drivers loop_bench 1000 3
