"""No thread left behind: 1,000 preempted runs of nested machines with a Concurrence, a
Supervisor, timeouts and action states keep the process's thread count constant."""
import threading
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import ScriptedServer, Sleeper
from smart_brain.statemachine import (ActionState, CBState, Concurrence, GoalGuard, MonitorState, Runner, StateMachine,
                                      Supervisor, Trigger)


class NullSub(object):
    def unregister(self):
        pass


def build():
    server = ScriptedServer()
    cc = Concurrence(outcomes=['done', 'preempted'], default_outcome='done')
    cc.add('SLEEP', Sleeper(10.0))
    cc.add('ACT', ActionState('/a', goal='g', client=server, guard=GoalGuard()))
    cc.add('MON', MonitorState('/t', None, lambda ud, m: True, subscribe=lambda *a: NullSub()))
    inner = StateMachine(outcomes=['done', 'preempted'])
    inner.add('CC', cc, transitions={'done': 'done', 'preempted': 'preempted'})
    body = StateMachine(outcomes=['done', 'preempted', 'aborted'])
    body.add('INNER', inner, transitions={'done': 'done', 'preempted': 'preempted', 'aborted': 'aborted'}, timeout=30.0)
    sup = Supervisor(body, [Trigger('never', lambda: False, CBState(lambda ud: 'resume', outcomes=['resume']))])
    return sup, cc['SLEEP'], server


class ThreadCountTest(unittest.TestCase):
    def test_thousand_preempted_runs_leave_no_thread(self):
        sup, sleeper, server = build()
        runner = Runner('threads')
        counts = []
        for i in range(1000):
            sleeper.started.clear()
            runner.start(sup)
            self.assertTrue(sleeper.started.wait(2.0))
            deadline = time.monotonic() + 2.0
            while len(server.goals) < i + 1 and time.monotonic() < deadline:
                time.sleep(0.0005)   # the action state has sent its goal
            runner.preempt()
            self.assertTrue(runner.wait(2.0), 'run %d did not end' % i)
            self.assertEqual(runner.outcome, 'preempted', 'run %d: %s %s' % (i, runner.outcome, runner.error))
            if i in (0, 999):
                counts.append(threading.active_count())
        self.assertEqual(counts[0], counts[1], 'threads after run 1: %d, after run 1000: %d' % tuple(counts))
        self.assertTrue(all(g.done() for g in server.goals), 'a goal was left running')
        self.assertEqual(len(server.goals), 1000)


if __name__ == '__main__':
    unittest.main()
