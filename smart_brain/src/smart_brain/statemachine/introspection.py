"""IntrospectionServer: publishes every container's structure and active states in the
smach_viewer format on <server>/smach/container_structure and <server>/smach/container_status
(smart_brain/SmachContainer*, field-for-field copies of smach_msgs).

Status is published from the executing thread at every transition (no polling thread);
structure is published at start and re-published every `structure_period` seconds by the
shared timer thread, so a late viewer still gets it. No threads per container.
"""
import pickle

import rospy
from smart_brain.msg import SmachContainerStatus, SmachContainerStructure

from smart_brain.statemachine import timers
from smart_brain.statemachine.container import Container


class IntrospectionServer(object):
    def __init__(self, server_name, state, path='/SM_ROOT', structure_period=2.0):
        self._ns = rospy.resolve_name(server_name).rstrip('/') + '/smach'
        self._root = state
        self._path = path
        self._period = structure_period
        self._containers = []
        self._timer = None
        self._stopped = False
        self._structure_pub = rospy.Publisher(self._ns + '/container_structure', SmachContainerStructure,
                                              queue_size=50)
        self._status_pub = rospy.Publisher(self._ns + '/container_status', SmachContainerStatus, queue_size=50)
        self._walk(state, path)

    def _walk(self, state, path):
        if not isinstance(state, Container):
            return
        self._containers.append((path, state))
        state.register_start_cb(lambda c, initial, p=path: self.publish_status(p, c))
        state.register_transition_cb(lambda c, active, p=path: self.publish_status(p, c))
        state.register_termination_cb(lambda c, last, outcome, p=path: self.publish_status(p, c, 'outcome: %s' % outcome))
        for label, child in state.get_children().items():
            self._walk(child, path + '/' + label)

    def start(self):
        self._stopped = False
        self.publish_structure()
        return self

    def stop(self):
        self._stopped = True
        if self._timer is not None:
            self._timer.cancel()

    def publish_structure(self):
        if self._stopped or rospy.is_shutdown():
            return
        for path, c in self._containers:
            edges = c.get_internal_edges()
            self._structure_pub.publish(SmachContainerStructure(
                path=path, children=list(c.get_children()),
                internal_outcomes=[e[0] for e in edges], outcomes_from=[e[1] for e in edges],
                outcomes_to=[e[2] for e in edges], container_outcomes=list(c.get_registered_outcomes())))
        for path, c in self._containers:
            self.publish_status(path, c)
        self._timer = timers.call_later(self._period, self.publish_structure)

    def publish_status(self, path, container, info=''):
        if self._stopped or rospy.is_shutdown():
            return
        try:
            local = pickle.dumps(container.userdata.snapshot(), 2)
        except Exception:   # unpicklable userdata (handles, callbacks): the viewer shows none
            local = pickle.dumps({}, 2)
        msg = SmachContainerStatus(path=path, initial_states=list(container.get_initial_states()),
                                   active_states=list(container.get_active_states()),
                                   local_data=local.decode('latin-1'), info=info)
        msg.header.stamp = rospy.Time.now()
        self._status_pub.publish(msg)
