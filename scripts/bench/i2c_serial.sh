#!/usr/bin/env bash
# I2C / serial benchmark: Logion's nine I2C boards (3 HBmotor, MCP23016, 4 SRF02,
# CMPS03) on one emulated bus and one loop group, achieved poll rates vs configured (from
# config/logion.yaml); then the beacon receiver on a pty at 100 messages/s: p50/p99 latency
# from a message's last byte written on the pty to its value on /hcl/beacons/state.
# Run from the repo root with the workspace sourced. Always exits 0 after printing.
root=$(cd "$(dirname "$0")/../.." && pwd)
python3 "$root/scripts/bench/i2c_serial_bench.py" "$root" || echo "i2c_serial bench: failed (see above)"
exit 0
