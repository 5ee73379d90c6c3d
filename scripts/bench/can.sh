#!/usr/bin/env bash
# CAN benchmark: the five eurobot2009 CAN boards with their emulators on the
# CAN-over-UDP bus (port 27020), then the motor board alone at 100 Hz and 1 kHz. Prints the
# achieved poll rates vs configured, p50/p99 latency from RTR to the new value on the state
# topic, p99 poll jitter, and the bus load as % of 1 Mbit/s. vcan: only where the kernel has
# AF_CAN (not on this machine: the SocketCAN path is exercised in a VM by
# scripts/can_socketcan_vm_test.sh, where software emulation makes timing figures meaningless).
# Run from the repo root with the workspace sourced. Always exits 0 after printing.
root=$(cd "$(dirname "$0")/../.." && pwd)
for phase in all 100 1000 vcan; do
  timeout 120 python3 "$root/scripts/bench/can_bench.py" "$root" "$phase" || echo "can bench phase $phase: failed (see above)"
done
exit 0
