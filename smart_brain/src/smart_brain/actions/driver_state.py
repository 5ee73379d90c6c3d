"""DriverState: an ActionState on one of the driver's actions (/hal/driver/*), whose
result `code` (hal_nodes/*Action results: REACHED, BLOCKED, ...) is kept for the caller."""
from smart_brain.statemachine import ActionState

DRIVER_NS = '/hal/driver/'


class DriverState(ActionState):
    def __init__(self, action, spec, goal=None, goal_cb=None, input_keys=(), exec_timeout=None, **kw):
        ActionState.__init__(self, DRIVER_NS + action, spec, goal=goal, goal_cb=goal_cb, input_keys=input_keys,
                             result_cb=self._keep_result, exec_timeout=exec_timeout, **kw)
        self.result = None

    def _keep_result(self, ud, status, result):
        self.result = result
        return None
