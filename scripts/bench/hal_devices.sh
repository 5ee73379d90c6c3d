#!/bin/bash
# HAL devices: cost of the devices' per-sample maths. Run from the repo root with
# the workspace sourced (make bench does both). Prints figures, exits 0.
set -e
bench=$(catkin_find --first-only hal_nodes device_models_bench 2>/dev/null || true)
if [ -z "$bench" ]; then echo "hal_devices: device_models_bench not built (make build)"; exit 0; fi
"$bench"
