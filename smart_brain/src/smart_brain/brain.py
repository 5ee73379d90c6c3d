"""The brain node: loads the strategy named by ~strategy and runs it.

Parameters:
  ~strategy        registered strategy name (required)
  ~rate            [Hz] execute() rate (default 10)
  ~device_timeout  [s] how long to wait for the strategy's HAL devices (default 10)
"""
import sys

import rospy

from smart_brain import strategy as strategies
from smart_brain.strategy import StrategyError


def hal_devices_present():
    """Names of HAL devices that publish something: /hal/<device>/<topic>."""
    present = set()
    for topic, _type in rospy.get_published_topics('/hal'):
        parts = topic.split('/')
        if len(parts) >= 4:
            present.add(parts[2])
    return present


def wait_for_devices(required, timeout):
    """Wait until every required device publishes; StrategyError naming the missing ones."""
    deadline = rospy.get_time() + timeout
    while not rospy.is_shutdown():
        missing = sorted(set(required) - hal_devices_present())
        if not missing:
            return
        if rospy.get_time() > deadline:
            raise StrategyError('HAL device(s) missing after %.0f s: %s (is hal_node running with them configured?)'
                                % (timeout, ', '.join('/hal/' + m for m in missing)))
        rospy.sleep(0.2)


def positive_param(name, default):
    value = rospy.get_param(name, default)
    if not isinstance(value, (int, float)) or isinstance(value, bool) or value <= 0:
        raise StrategyError('parameter %s = %r: must be a number > 0' % (rospy.resolve_name(name), value))
    return float(value)


def main():
    rospy.init_node('brain')
    try:
        if not rospy.has_param('~strategy'):
            raise StrategyError('missing required parameter %s; allowed values: %s'
                                % (rospy.resolve_name('~strategy'), ', '.join(strategies.available())))
        name = rospy.get_param('~strategy')
        rate_hz = positive_param('~rate', 10.0)
        device_timeout = positive_param('~device_timeout', 10.0)
        strategy = strategies.create(str(name))
        rospy.loginfo('brain: strategy %s: %s', strategy.name, strategy.description)
        wait_for_devices(strategy.required_devices, device_timeout)
    except StrategyError as e:
        rospy.logfatal('brain: %s', e)
        sys.exit(2)

    strategy.initialize()
    rate = rospy.Rate(rate_hz)
    try:
        while not rospy.is_shutdown():
            if strategy.execute() is False:
                rospy.loginfo('brain: strategy %s finished', strategy.name)
                break
            rate.sleep()
    except rospy.ROSInterruptException:
        pass
    finally:
        strategy.finalize()
