"""Shared helpers of the CAN rostests (test_can_*.py): a CAN-over-UDP participant (the wire
format of hcl_drivers/transport/udp_can_bus.h) to inject frames like a second node or a CAN
controller reporting errors, and /diagnostics by hardware id (the recorders are test_support's)."""
import socket
import struct
import threading
import time

from diagnostic_msgs.msg import DiagnosticArray
from test_support import Recorder, value  # noqa: F401 (the CAN tests import them from here)

KIND_FRAME, KIND_HELLO = 1, 2
FLAG_RTR, FLAG_EXT, FLAG_ERR = 1, 2, 4
ERR_BUSOFF, ERR_RESTARTED = 0x040, 0x100


def encode(can_id, data=b'', rtr=False, error=False, dlc=None):
    data = bytes(data)
    flags = (FLAG_RTR if rtr else 0) | (FLAG_ERR if error else 0)
    n = len(data) if dlc is None else dlc
    return b'CN' + struct.pack('<BBIB', KIND_FRAME, flags, can_id, n) + data.ljust(8, b'\0')


class CanUdp(object):
    """A client participant of the UDP CAN bus on 127.0.0.1:port (the hub must exist)."""

    def __init__(self, port):
        self.hub = ('127.0.0.1', port)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(('127.0.0.1', 0))
        self.sock.settimeout(0.05)
        self.lock = threading.Lock()
        self.frames = []  # (monotonic time, id, flags, data)
        self.running = True
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()
        time.sleep(0.3)  # registered with the hub by the first HELLOs

    def _run(self):
        next_hello = 0.0
        while self.running:
            now = time.monotonic()
            if now >= next_hello:
                self.sock.sendto(b'CN' + bytes([KIND_HELLO]) + bytes(14), self.hub)
                next_hello = now + 0.2
            try:
                d, _ = self.sock.recvfrom(64)
            except (socket.timeout, OSError):
                continue
            if len(d) != 17 or d[:2] != b'CN' or d[2] != KIND_FRAME:
                continue
            flags, can_id, dlc = d[3], struct.unpack('<I', d[4:8])[0], d[8]
            with self.lock:
                self.frames.append((time.monotonic(), can_id, flags, d[9:9 + dlc]))

    def send(self, can_id, data=b'', rtr=False, error=False, dlc=None):
        self.sock.sendto(encode(can_id, data, rtr, error, dlc), self.hub)

    def seen(self, since, can_id):
        with self.lock:
            return [f for f in self.frames if f[0] >= since and f[1] == can_id]

    def close(self):
        self.running = False


class Diagnostics(Recorder):
    def __init__(self):
        Recorder.__init__(self, '/diagnostics', DiagnosticArray)

    def status(self, hardware_id):
        with self.lock:
            for _, arr in reversed(self.items):
                for s in arr.status:
                    if s.hardware_id == hardware_id:
                        return s
        return None

    def wait_status(self, hardware_id, pred, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            s = self.status(hardware_id)
            if s is not None and pred(s):
                return s
            time.sleep(0.05)
        return self.status(hardware_id)


def truth_value(msg, name):
    return msg.values[msg.names.index(name)]
