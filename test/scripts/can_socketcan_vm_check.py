#!/usr/bin/env python3
"""Inside the SocketCAN VM: wait for the motor board (with its emulator) to answer, command a
motor, and wait for the can-utils-injected PDO on the HMI board's state topic. Prints
key=value lines for the host-side test (can_socketcan_vm_test.sh)."""
import sys
import time

import rospy
from hcl_drivers.msg import HmiBoardState, MotorBoardState, MotorCommand

got = {}


def on_motor(m):
    if m.node.answering:
        got['motor'] = m


def on_hmi(m):
    if m.keys == 5 and m.last_key == 15 and m.key_presses == 3:
        got['hmi'] = m


rospy.init_node('vm_check', disable_signals=True)
rospy.Subscriber('/hcl/motor_board/state', MotorBoardState, on_motor)
rospy.Subscriber('/hcl/hmi_inject/state', HmiBoardState, on_hmi)
pub = rospy.Publisher('/hcl/motor_board/motor/left/command', MotorCommand, queue_size=1)
deadline = time.monotonic() + 300.0  # software-emulated VM: ROS starts slowly
while time.monotonic() < deadline and 'motor' not in got:
    time.sleep(0.1)
print('motor_answering=%d' % ('motor' in got))
if 'motor' in got:
    print('motor_nmt=%s' % got['motor'].node.nmt_state)
t_end = time.monotonic() + 3.0
while time.monotonic() < t_end:  # a fresh command (within command_timeout) for a few polls
    pub.publish(MotorCommand(header=rospy.Header(stamp=rospy.Time.now()), name='left', value=300))
    time.sleep(0.1)
applied = got.get('motor')
print('motor_pwm_applied=%s' % (list(applied.pwm_applied) if applied else None))
while time.monotonic() < deadline and 'hmi' not in got:
    time.sleep(0.1)
print('injected_pdo_on_state=%d' % ('hmi' in got))
sys.exit(0 if 'motor' in got and 'hmi' in got else 1)
