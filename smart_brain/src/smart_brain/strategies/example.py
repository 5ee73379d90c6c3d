"""The skeleton robot's strategy: the lamp follows the dial.

Reads the example device's dial position (HAL) and commands the lamp brightness back
through HAL, so a value crosses all three layers in both directions.
"""
import rospy
from hal_nodes.msg import ExampleReading
from std_msgs.msg import Float64

from smart_brain.strategy import Strategy, register


@register
class ExampleStrategy(Strategy):
    name = 'example'
    description = 'skeleton robot: lamp brightness follows the dial position'
    required_devices = ('example_device',)
    #: a demo, not a match: no start signal, no match end
    timed = False

    #: a reading older than this is not acted on [s]
    max_reading_age = 0.5

    def initialize(self):
        self._reading = None
        self._received_at = None
        self._lamp = rospy.Publisher('/hal/example_device/lamp', Float64, queue_size=1)
        self._sub = rospy.Subscriber('/hal/example_device/reading', ExampleReading, self._on_reading, queue_size=1)

    def _on_reading(self, msg):
        self._reading = msg
        self._received_at = rospy.get_time()

    def execute(self):
        if self._reading is None or rospy.get_time() - self._received_at > self.max_reading_age:
            rospy.logwarn_throttle(2.0, 'example: no fresh dial reading, lamp left to time out')
            return True
        self._lamp.publish(Float64(self._reading.position))
        return True

    def finalize(self):
        self._sub.unregister()
        self._lamp.publish(Float64(0.0))
