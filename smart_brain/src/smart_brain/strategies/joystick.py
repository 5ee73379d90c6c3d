"""Joystick: drive by hand from the HAL joystick device; buttons call effector callbacks.

Axes and buttons are the joystick device's names (hal_nodes/JoystickState on
~joystick/state_topic, edges as hal_nodes/JoystickEvent on ~joystick/events_topic).
Config (~joystick): linear_axis, angular_axis, max_linear [m/s], max_angular [rad/s],
deadman (a button that must be held to drive; '' none), max_age [s] (pad state older than
this, by its stamp or since it arrived: zero speed), buttons {button name: callback} with
callbacks from CALLBACKS below.
Twists go to /hal/drive/cmd_vel as the pad's states arrive; when the pad goes stale a
single zero is sent (the drive effector's own command timeout stops the wheels anyway).
"""
import threading

import rospy

from smart_brain.slave import BrainSlave
from smart_brain.statemachine import clock
from smart_brain.strategy import Strategy, StrategyError, register

CMD_VEL = '/hal/drive/cmd_vel'


def _hand(command, height=0.0):
    def cb(strategy):
        from smart_brain.actions.hand import hand
        strategy.slave.start('hand_%s_%s' % (command, clock.now()), hand(command, height=height))
    return cb


def _effectors(on):
    def cb(strategy):
        from std_srvs.srv import Trigger
        name = '/effectors/activate' if on else '/effectors/deactivate'
        try:
            rospy.ServiceProxy(name, Trigger)()
        except (rospy.ServiceException, rospy.ROSException) as e:
            rospy.logerr('joystick: %s failed: %s', name, e)
    return cb


def _stop(strategy):
    strategy.slave.stop()
    strategy.publish(0.0, 0.0)


#: what a button can do (config ~joystick/buttons: {button: callback})
CALLBACKS = {
    'hand_open': _hand('open'),
    'hand_close': _hand('close'),
    'hand_lift': _hand('lift', 0.06),
    'hand_lower': _hand('lift', 0.0),
    'effectors_on': _effectors(True),
    'effectors_off': _effectors(False),
    'stop': _stop,
}


@register
class JoystickStrategy(Strategy):
    name = 'joystick'
    description = 'drive by hand with the gamepad; buttons call effector callbacks (config)'
    required_devices = ('joystick',)

    def read_config(self, brain, table):
        Strategy.read_config(self, brain, table)
        p = self.params
        self.linear_axis = p.value('linear_axis', 'left_y', str, meaning="the stick axis (HAL's axis name) for speed")
        self.angular_axis = p.value('angular_axis', 'left_x', str, meaning='the stick axis for turning')
        self.max_linear = p.value('max_linear', 0.4, float, meaning='[m/s] speed at full stick')
        self.max_angular = p.value('max_angular', 2.0, float, meaning='[rad/s] turn rate at full stick')
        self.deadman = p.value('deadman', '', str, meaning="a button held while driving ('': none)")
        self.max_age = p.value('max_age', 0.3, float, meaning='[s] an older pad state stops the robot')
        self.state_topic = p.value('state_topic', '/hal/joystick/state', str, meaning="the pad's JoystickState topic")
        self.events_topic = p.value('events_topic', '/hal/joystick/events', str,
                                    meaning="the pad's JoystickEvent topic (button presses)")
        buttons = p.value('buttons', {}, dict, meaning='button name: callback (%s)' % ', '.join(sorted(CALLBACKS)))
        self.bindings = {}
        for button, callback in buttons.items():
            if callback not in CALLBACKS:
                raise StrategyError("parameter %s/buttons/%s = '%s': allowed values: %s"
                                    % (p.ns, button, callback, ', '.join(sorted(CALLBACKS))))
            self.bindings[button] = CALLBACKS[callback]

    def initialize(self):
        from geometry_msgs.msg import Twist
        from hal_nodes.msg import JoystickEvent, JoystickState
        self.ensure_config()
        self.slave = BrainSlave()
        self._lock = threading.Lock()
        self._last_state = None   # when the last usable state arrived (the brain's clock)
        self._last_stamp = None   # its stamp (ROS time)
        self._stale_sent = True
        self._stopped = False
        self._Twist = Twist
        self._pub = rospy.Publisher(CMD_VEL, Twist, queue_size=1)
        self._subs = [
            rospy.Subscriber(self.state_topic, JoystickState, self._on_state, queue_size=1),
            rospy.Subscriber(self.events_topic, JoystickEvent, self._on_event, queue_size=20),
        ]

    def publish(self, linear, angular):
        t = self._Twist()
        t.linear.x, t.angular.z = linear, angular
        self._pub.publish(t)

    def command_for(self, msg):
        """(linear, angular) for a JoystickState."""
        axes = dict(zip(msg.axis_names, msg.axes))
        held = dict(zip(msg.button_names, msg.buttons))
        if self.deadman and not held.get(self.deadman, False):
            return 0.0, 0.0
        clamp = lambda v: max(-1.0, min(1.0, v))  # noqa: E731
        # HAL's X axes read +1 to the right (Linux's convention); a stick to the right turns the
        # robot right, which is negative angular z (REP-103): hence the minus.
        return (clamp(axes.get(self.linear_axis, 0.0)) * self.max_linear,
                -clamp(axes.get(self.angular_axis, 0.0)) * self.max_angular)

    def _on_state(self, msg):
        if self._stopped:
            return
        # The pad's data ages from its stamp: HAL republishes the last state it has until that
        # state is its own max_input_age old, and counting max_age from receiving it would add
        # the two timeouts. Without a stamp, from its arrival.
        stamp = None if msg.header.stamp.is_zero() else msg.header.stamp
        if stamp is not None and (rospy.Time.now() - stamp).to_sec() > self.max_age:
            return
        with self._lock:
            self._last_state = clock.now()
            self._last_stamp = stamp
            self._stale_sent = False
        self.publish(*self.command_for(msg))

    def _on_event(self, msg):
        if self._stopped or not msg.pressed:
            return
        cb = self.bindings.get(msg.button)
        if cb is not None:
            rospy.loginfo('joystick: %s -> %s', msg.button, cb.__name__ if hasattr(cb, '__name__') else cb)
            try:
                cb(self)
            except Exception as e:
                rospy.logerr('joystick: button %s: %s', msg.button, e)

    def execute(self):
        if self._stopped:
            return False
        with self._lock:
            stale = (self._last_state is None or clock.now() - self._last_state > self.max_age or
                     (self._last_stamp is not None and (rospy.Time.now() - self._last_stamp).to_sec() > self.max_age))
            send = stale and not self._stale_sent
            if send:
                self._stale_sent = True
        if send:
            rospy.logwarn('joystick: pad stale, zero speed')
            self.publish(0.0, 0.0)
        return True

    def stop(self):
        self._stopped = True
        self.slave.stop()

    def finalize(self):
        self.stop()
        for s in self._subs:
            s.unregister()
        self.publish(0.0, 0.0)
