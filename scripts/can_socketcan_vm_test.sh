#!/usr/bin/env bash
# The real SocketCAN test (issue 4). This machine's kernel has no AF_CAN, so it boots Debian's
# kernel (which has vcan) in a virtme-ng VM over the host's own file system, creates vcan0 and
# runs test/scripts/can_socketcan_vm_inner.sh there: our drivers and emulator on
# socketcan://vcan0, candump -L recording, cansend answering RTRs. Then it checks here, byte-exact,
# that candump saw our NMT, SDO, RTR and PDO frames, and that the injected PDO reached the
# board's state topic. Where the kernel has AF_CAN and vcan, the inner script runs directly.
#
#   scripts/can_socketcan_vm_test.sh [junit.xml] [devel space] [auto]     (as root)
# Needs (installed here on demand, only when the VM runs; `make deps` does not install them):
# linux-image-amd64, qemu-system-x86, busybox-static, python3-venv, virtme-ng (pip, into
# build/can_vm_venv).
# This host exposes no hardware virtualisation to us (/dev/kvm but no vmx/svm: KVM fails), so
# the VM runs in software emulation: ~2 min to boot to vcan0 on an idle machine, 4-7 min with
# ROS inside on a loaded one. Measured 2026-11-23 (load average 19 falling to 4): 575 s in all;
# in the guest vcan0 was up at 103 s, rosmaster answered at 164 s, the nodes started at 169 s.
# A second run at load average 4-7: the VM took 208 s (nodes started at 60 s, checks done at 171 s).
# It swings from 3.5 to 10 min with the machine's load, so it stays opt-in rather than risk the
# default `make test` (whole suite ~14 min) on a loaded CI machine.
# With `auto` (how `make test` calls it) the VM only runs when
# CAN_VM_TEST=1; otherwise the test is reported as skipped with that reason. On a kernel with
# AF_CAN + vcan it always runs, directly on vcan0, in seconds.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
xml=${1:-$root/build/test_results/system_tests/can_socketcan_vm.xml}
devel=${2:-$root/devel}
mode=${3:-always}
inner=$root/test/scripts/can_socketcan_vm_inner.sh
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
mkdir -p "$(dirname "$xml")"
out=$(mktemp -d /tmp/can_vm.XXXXXX)
chmod 777 "$out"
t0=$(date +%s)

junit() {  # junit <name> <ok 0/1/skip> <message>
  cases+="  <testcase classname=\"can_socketcan\" name=\"$1\">"
  if [ "$2" = skip ]; then cases+="<skipped message=\"$3\"/>"; ((skipped++))
  elif [ "$2" != 0 ]; then cases+="<failure message=\"$(echo "$3" | sed 's/&/\&amp;/g; s/"/\&quot;/g; s/</\&lt;/g')\"/>"; ((failed++)); fi
  cases+="</testcase>"$'\n'; ((total++))
  echo "  [$([ "$2" = 0 ] && echo ok || echo "$2")] $1 ${3:-}"
}
cases=""; total=0; failed=0; skipped=0
finish() {
  {
    echo '<?xml version="1.0" encoding="UTF-8"?>'
    echo "<testsuite name=\"can_socketcan_vm\" tests=\"$total\" failures=\"$failed\" skipped=\"$skipped\" errors=\"0\" time=\"$(( $(date +%s) - t0 ))\">"
    echo -n "$cases"
    echo '</testsuite>'
  } > "$xml"
  echo "can_socketcan_vm: $total checks, $failed failed, $skipped skipped in $(( $(date +%s) - t0 )) s (logs: $out)"
  exit 0
}

have_af_can() { python3 -c 'import socket; socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)' 2>/dev/null; }

if have_af_can && modprobe vcan 2>/dev/null && ! ip link show vcan0 >/dev/null 2>&1; then
  echo "this kernel has AF_CAN and vcan: running on vcan0 directly"
  bash "$inner" "$out" "$devel"
  ip link del vcan0 2>/dev/null
elif [ "$mode" = auto ] && [ "${CAN_VM_TEST:-0}" != 1 ]; then
  junit socketcan_vcan0 skip "no AF_CAN in this kernel; the VM test takes minutes in software emulation: run scripts/can_socketcan_vm_test.sh or set CAN_VM_TEST=1"
  finish
else
  kernel=$(ls /boot/vmlinuz-* 2>/dev/null | sort -V | tail -n 1)
  if [ -z "$kernel" ] || ! command -v qemu-system-x86_64 >/dev/null || ! command -v busybox >/dev/null ||
     ! dpkg -s python3-venv >/dev/null 2>&1; then
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        linux-image-amd64 qemu-system-x86 busybox-static python3-venv; } >/dev/null 2>&1
    kernel=$(ls /boot/vmlinuz-* 2>/dev/null | sort -V | tail -n 1)
  fi
  venv=$root/build/can_vm_venv
  if [ ! -x "$venv/bin/vng" ]; then
    python3 -m venv "$venv" >/dev/null 2>&1 && "$venv/bin/pip" install -q virtme-ng >/dev/null 2>&1
  fi
  if [ -z "$kernel" ] || [ ! -x "$venv/bin/vng" ] || ! command -v qemu-system-x86_64 >/dev/null; then
    junit vm_boot skip "no VM possible here: kernel=${kernel:-none}, vng=$([ -x "$venv/bin/vng" ] && echo yes || echo no), qemu=$(command -v qemu-system-x86_64 || echo no)"
    finish
  fi
  echo "booting $kernel in virtme-ng (software emulation)"
  # KVM fails on this host (MSR error): software emulation, slower but reliable.
  PATH=$venv/bin:$PATH timeout 600 vng --disable-kvm --memory 1G --rwdir="$out" --run "$kernel" \
    --exec "bash $inner $out $devel" > "$out/vng.log" 2>&1
  echo "vng exit $? after $(( $(date +%s) - t0 )) s"
fi

if [ ! -f "$out/result" ]; then
  junit vm_boot 1 "the VM did not run the test: $(tail -n 3 "$out/vng.log" 2>/dev/null | tr '\n' ' ')"
  finish
fi
junit vm_boot 0 "$(head -c 200 "$out/result")"
frames=$(awk '{print $3}' "$out/candump.log" 2>/dev/null)
expect() {  # expect <name> <regex of a candump -L frame>
  if echo "$frames" | grep -qE "^$2\$"; then junit "$1" 0 "$2"; else junit "$1" 1 "candump never saw $2"; fi
}
expect nmt_start_node_10 '000#010A'
expect nmt_start_node_20 '000#0114'
expect emulator_boot_up '70A#00'
expect sdo_write_watchdog_200ms '60A#2B012000C8000000'
expect sdo_write_ack '58A#6001200000000000'
expect sdo_read_firmware_version '60A#4002200000000000'
expect sdo_read_answer '58A#4B02200003010000'
expect rtr_encoders '18A#R8?'
expect rtr_status '28A#R5?'
expect tpdo_status_answer '28A#[0-9A-F]{10}'
expect rpdo_motor_command_300 '20A#2C010000'
expect rtr_hmi_keys '194#R4?'
expect cansend_injected_pdo '194#05000F03'
check=$(cat "$out/check.txt" 2>/dev/null)
if echo "$check" | grep -q 'motor_answering=1'; then junit motor_board_answers_on_vcan0 0 ""; else junit motor_board_answers_on_vcan0 1 "$check"; fi
if echo "$check" | grep -q 'motor_pwm_applied=\[300, 0\]'; then junit firmware_applies_command 0 ""; else junit firmware_applies_command 1 "$check"; fi
if echo "$check" | grep -q 'injected_pdo_on_state=1'; then junit injected_pdo_reaches_state_topic 0 ""; else junit injected_pdo_reaches_state_topic 1 "$check"; fi
finish
