#!/usr/bin/env bash
# Runs INSIDE the virtme-ng VM (Debian's kernel, which has AF_CAN and vcan) started by
# scripts/can_socketcan_vm_test.sh: a real SocketCAN bus vcan0 with
#   * the motor board driver (node 10) and its firmware emulator, both on socketcan://vcan0;
#   * an HMI board driver (node 20) whose firmware is can-utils: every RTR it sends is answered
#     by `cansend`, so an injected PDO must reach /hcl/hmi_inject/state;
#   * candump -L logging every frame for the host to check byte-exact;
#   * then, with the driver stopped, the hardware doctor's engine (board_doctor) on vcan0.
#   can_socketcan_vm_inner.sh <out dir (writable)> <devel space>
set -u
out=$1; devel=$2
here=$(cd "$(dirname "$0")" && pwd)
export PATH=/usr/bin:/bin:/usr/sbin:/sbin HOME=/tmp ROS_HOME=/tmp/ros PYTHONNOUSERSITE=1
mkdir -p /tmp/ros
exec > "$out/inner.log" 2>&1
log() { echo "[$(cut -d' ' -f1 /proc/uptime)] $*"; }
ip link set lo up
set +u  # setup.bash reads unset variables
# shellcheck disable=SC1091
source "$devel/setup.bash"
export ROS_MASTER_URI=http://127.0.0.1:11611 ROS_HOSTNAME=127.0.0.1
# Software emulation makes every Python start slow (rosmaster ~40 s): start it first, while
# vcan0 comes up.
rosmaster --core -p 11611 > /tmp/ros/master.log 2>&1 &
modprobe vcan && ip link add vcan0 type vcan && ip link set up vcan0 || { log "no vcan"; echo "vcan=fail" > "$out/result"; exit 1; }
log "vcan0 up: $(ip -brief link show vcan0)"
candump -L vcan0 > "$out/candump.log" &
candump_pid=$!
for _ in $(seq 1 1200); do (echo > /dev/tcp/127.0.0.1/11611) 2>/dev/null && break; sleep 0.1; done
log "master up"
cat > /tmp/params.yaml <<'YAML'
hcl:
  motor_board: {type: MotorBoard, bus: "socketcan://vcan0", node_id: 10, rate: 20, motors: [left, right], answer_timeout: 0.2, sdo_timeout: 0.5, command_timeout: 1.0}
  hmi_inject: {type: HmiBoard, bus: "socketcan://vcan0", node_id: 20, rate: 2, answer_timeout: 0.45, stale_timeout: 5.0}
firmware:
  motor_board: {type: MotorBoard, bus: "socketcan://vcan0", node_id: 10, motors: [left, right]}
YAML
rosparam load /tmp/params.yaml /
log "params loaded"
# The firmware of node 20 is can-utils: answer each RTR on 0x194 with cansend. (candump's
# 8-digit filter form would add the extended flag, so filter on the id and keep RTRs only.)
(
  while true; do
    line=$(candump -n 1 -L vcan0,194:7FF 2>/dev/null) || break
    case "$line" in *"194#R"*) cansend vcan0 194#05000F03 ;; esac
  done
) &
# The executables directly: rosrun would spend tens of seconds in Python finding them.
"$devel/lib/robot_sim/firmware_host" __name:=firmware > /tmp/ros/firmware.log 2>&1 &
"$devel/lib/hcl_drivers/hcl_node" __name:=hcl > /tmp/ros/hcl.log 2>&1 &
log "nodes started"
python3 "$here/can_socketcan_vm_check.py" > "$out/check.txt" 2>&1
rc=$?
log "check rc=$rc"
# The hardware doctor over SocketCAN, with the product stopped: it must find the emulated motor
# board (SDO 0x1000/0x1018, heartbeat) and scan vcan0 for strangers; candump records its requests.
kill "$(pgrep -f "$devel/lib/hcl_drivers/hcl_node")" 2>/dev/null
sleep 0.5
"$devel/lib/hcl_drivers/board_doctor" _boards:=motor_board _load_window:=1.0 > "$out/doctor.json" 2> /tmp/ros/doctor.log
log "doctor rc=$?"
sleep 0.5
kill "$candump_pid" 2>/dev/null && wait "$candump_pid" 2>/dev/null  # candump flushes its log as it exits
cp /tmp/ros/*.log "$out/" 2>/dev/null
echo "check=$rc" > "$out/result"
