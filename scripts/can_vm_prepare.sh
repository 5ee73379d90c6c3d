#!/usr/bin/env bash
# Installs what the real SocketCAN test (scripts/can_socketcan_vm_test.sh) needs to boot a VM,
# when this machine needs one: a kernel without AF_CAN, or no right to create vcan0 (containers).
# Debian's kernel (linux-image-amd64, which has vcan), qemu-system-x86, busybox-static and
# virtme-ng (pip, into build/can_vm_venv). Nothing is installed where the kernel has AF_CAN and
# vcan0 can be created (the test then runs on vcan0 directly), or with CAN_VM_TEST=0.
#
#   scripts/can_vm_prepare.sh              install now (waits for a background run to finish)
#   scripts/can_vm_prepare.sh --background start installing and return at once (make test does
#                                          this before building: the downloads overlap the build)
# Prints one line: "ready: <the VM kernel>", "not needed: ..." or "missing: ..."; the log is
# build/can_vm_prepare.log.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
mkdir -p "$root/build"
lock=$root/build/can_vm_prepare.lock
log=$root/build/can_vm_prepare.log
venv=$root/build/can_vm_venv

have_af_can() { python3 -c 'import socket; socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)' 2>/dev/null; }
# The test creates (and deletes) vcan0 itself: it must be free, and creatable.
vcan_possible() { have_af_can && modprobe vcan 2>/dev/null && ! ip link show vcan0 >/dev/null 2>&1 &&
  ip link add vcan_probe type vcan 2>/dev/null && ip link del vcan_probe; }
vm_kernel() { ls /boot/vmlinuz-* 2>/dev/null | sort -V | tail -n 1; }
missing() {
  local m=""
  [ -n "$(vm_kernel)" ] || m+=" kernel"
  command -v qemu-system-x86_64 >/dev/null || m+=" qemu"
  command -v busybox >/dev/null || m+=" busybox"
  [ -x "$venv/bin/vng" ] || m+=" virtme-ng"
  echo "$m"
}

install() {
  if [ -n "$(missing | grep -E 'kernel|qemu|busybox')" ] || ! dpkg -s python3-venv >/dev/null 2>&1; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      linux-image-amd64 qemu-system-x86 busybox-static python3-venv
  fi
  if [ ! -x "$venv/bin/vng" ]; then
    rm -rf "$venv"
    python3 -m venv "$venv" && "$venv/bin/pip" install -q virtme-ng
  fi
}

if [ "${CAN_VM_TEST:-1}" = 0 ]; then echo "not needed: CAN_VM_TEST=0"; exit 0; fi
if vcan_possible; then echo "not needed: this kernel has AF_CAN and vcan0 can be created"; exit 0; fi
if [ "${1:-}" = --background ]; then
  # setsid: the install outlives make's shell; flock: the test waits for it.
  setsid flock "$lock" bash -c "$(declare -f missing vm_kernel install); venv='$venv'; t0=\$(date +%s); install;
    echo \"prepared in \$(( \$(date +%s) - t0 )) s\"" > "$log" 2>&1 < /dev/null &
  echo "installing the SocketCAN VM's kernel, qemu and virtme-ng in the background (log: $log)"
  exit 0
fi
flock "$lock" bash -c "$(declare -f missing vm_kernel install); venv='$venv'; install" >> "$log" 2>&1
m=$(missing)
if [ -n "$m" ]; then echo "missing:$m (see $log)"; exit 1; fi
echo "ready: $(vm_kernel)"
