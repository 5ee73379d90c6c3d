"""WorldView: what a match strategy knows of the table from HAL: the robot's pose
(/mcl/pose) and the newest game elements the vision device saw (hal_nodes/GameElements)."""
import math
import threading

from robot_core.geometry import yaw_of
from smart_brain.statemachine import clock


class WorldView(object):
    def __init__(self, table, vision_topic='/hal/vision/elements', pose_topic='/mcl/pose', max_age=1.0,
                 border_margin=0.0, on_elements=None):
        """`table`: (length, width) [m] (the strategy's TableSettings.size); `on_elements(stamp,
        [(kind, x, y)])`, if given, is called with each camera frame's elements."""
        import rospy
        self._on_elements_cb = on_elements
        #: [m] elements seen closer than this to a border are left out: a detection on the border
        #: line is no element, and one lying against the border cannot be taken without pushing it
        self.border_margin = float(border_margin)
        self.table = tuple(table)
        from geometry_msgs.msg import PoseWithCovarianceStamped
        from hal_nodes.msg import GameElements
        self.max_age = max_age
        self._lock = threading.Lock()
        self._pose = None
        self._elements = (0.0, [])
        self._subs = [rospy.Subscriber(pose_topic, PoseWithCovarianceStamped, self._on_pose, queue_size=1),
                      rospy.Subscriber(vision_topic, GameElements, self._on_elements, queue_size=1)]

    def _on_pose(self, msg):
        p = msg.pose.pose
        yaw = yaw_of(p.orientation)
        with self._lock:
            self._pose = (p.position.x, p.position.y, yaw)

    def _on_elements(self, msg):
        items = [(e.kind, e.pose.pose.position.x, e.pose.pose.position.y) for e in msg.elements]
        now = clock.now()
        with self._lock:
            self._elements = (now, items)
        if self._on_elements_cb is not None:
            self._on_elements_cb(now, items)

    def pose(self):
        with self._lock:
            return self._pose

    def elements(self, kinds):
        """[(kind, x, y)] of the wanted kinds seen within max_age, nearest first."""
        with self._lock:
            stamp, items = self._elements
            pose = self._pose
        if clock.now() - stamp > self.max_age:
            return []
        m = self.border_margin
        items = [e for e in items if e[0] in kinds and m <= e[1] <= self.table[0] - m and m <= e[2] <= self.table[1] - m]
        if pose is not None:
            items.sort(key=lambda e: math.hypot(e[1] - pose[0], e[2] - pose[1]))
        return items


def approach_pose(robot, target, distance):
    """The pose `distance` before `target` on the line from `robot`, facing it."""
    rx, ry = robot[0], robot[1]
    tx, ty = target[0], target[1]
    heading = math.atan2(ty - ry, tx - rx)
    return (tx - distance * math.cos(heading), ty - distance * math.sin(heading), heading)


def nearest_first(start, points):
    """Greedy nearest-neighbour order of points from start (a short harvest route)."""
    left = list(points)
    route = []
    cur = start
    while left:
        nxt = min(left, key=lambda p: math.hypot(p[0] - cur[0], p[1] - cur[1]))
        left.remove(nxt)
        route.append(nxt)
        cur = nxt
    return route
