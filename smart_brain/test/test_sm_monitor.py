"""MonitorState: condition on a message feed; valid / invalid / aborted on timeout / preempted."""
import threading
import time
import unittest

from smart_brain.statemachine import CBState, MonitorState, Runner, StateMachine, Supervisor, Trigger


class Feed(object):
    """A message source standing in for a topic: subscribe() as rospy.Subscriber would."""

    def __init__(self):
        self.callbacks = []

    def subscribe(self, topic, msg_type, cb):
        self.callbacks.append(cb)
        feed = self

        class Sub(object):
            def unregister(self):
                feed.callbacks.remove(cb)
        return Sub()

    def publish(self, msg):
        for cb in list(self.callbacks):
            cb(msg)


def publish_later(feed, values, period=0.02):
    def run():
        for v in values:
            time.sleep(period)
            feed.publish(v)
    threading.Thread(target=run, daemon=True).start()


class MonitorTest(unittest.TestCase):
    def test_invalid_when_the_condition_says_stop(self):
        feed = Feed()
        mon = MonitorState('/q', None, lambda ud, m: m < 3, subscribe=feed.subscribe)
        publish_later(feed, [1, 2, 3, 4])
        self.assertEqual(mon.run(None), 'invalid')
        self.assertEqual(feed.callbacks, [], 'subscription left behind')

    def test_valid_after_max_checks(self):
        feed = Feed()
        mon = MonitorState('/q', None, lambda ud, m: True, max_checks=3, subscribe=feed.subscribe)
        publish_later(feed, [1, 2, 3, 4, 5])
        self.assertEqual(mon.run(None), 'valid')

    def test_a_silent_topic_aborts_after_the_timeout(self):
        feed = Feed()
        mon = MonitorState('/q', None, lambda ud, m: True, timeout=0.2, subscribe=feed.subscribe)
        t0 = time.monotonic()
        self.assertEqual(mon.run(None), 'aborted')
        self.assertLess(time.monotonic() - t0, 0.5)

    def test_preempt_ends_the_wait_at_once(self):
        feed = Feed()
        mon = MonitorState('/q', None, lambda ud, m: True, subscribe=feed.subscribe)
        runner = Runner('m')
        runner.start(mon)
        time.sleep(0.1)
        t0 = time.monotonic()
        runner.preempt()
        self.assertTrue(runner.wait(1.0))
        self.assertLess(time.monotonic() - t0, 0.1)
        self.assertEqual(runner.outcome, 'preempted')

    def test_condition_sees_userdata(self):
        feed = Feed()
        sm = StateMachine(outcomes=['above', 'timeout', 'preempted'])
        sm.userdata.limit = 5
        sm.add('WATCH', MonitorState('/q', None, lambda ud, m: m <= ud.limit, input_keys=['limit'],
                                     subscribe=feed.subscribe, timeout=2.0),
               transitions={'invalid': 'above', 'valid': 'timeout', 'aborted': 'timeout', 'preempted': 'preempted'})
        publish_later(feed, [1, 4, 6], 0.05)
        self.assertEqual(sm.execute(), 'above')


class SupervisorPreemptTest(unittest.TestCase):
    def test_preempt_while_the_handler_runs_ends_with_preempted(self):
        feed = Feed()
        body = StateMachine(outcomes=['done', 'preempted'])
        body.add('WATCH', MonitorState('/q', None, lambda ud, m: True, subscribe=feed.subscribe),
                 transitions={'valid': 'done', 'invalid': 'done', 'aborted': 'done', 'preempted': 'preempted'})
        entered = threading.Event()

        def slow_handler(ud):
            entered.set()
            return 'resume'

        class SlowHandler(CBState):
            def execute(self, ud):
                entered.set()
                return 'preempted' if self.wait(10.0) == 'preempted' else 'resume'
        flag = {'v': False}
        sup = Supervisor(body, [Trigger('t', lambda: flag['v'], SlowHandler(slow_handler, outcomes=['resume', 'preempted']))])
        runner = Runner('s')
        runner.start(sup)
        time.sleep(0.1)
        flag['v'] = True
        self.assertTrue(entered.wait(1.0))
        t0 = time.monotonic()
        runner.preempt()
        self.assertTrue(runner.wait(1.0))
        self.assertLess(time.monotonic() - t0, 0.2)
        self.assertEqual(runner.outcome, 'preempted')


if __name__ == '__main__':
    unittest.main()
