"""Persistent worker threads, created once and reused on every entry of their owner.

smach started a thread per Concurrence child per entry; here a Concurrence (or a Runner)
owns its workers for its whole life, so the process's thread count stays constant however
often a state is entered and left.
"""
import queue
import threading


class Worker(object):
    """One daemon thread running submitted callables one after another."""

    def __init__(self, name):
        self._jobs = queue.Queue()
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def submit(self, fn):
        self._jobs.put(fn)

    def _run(self):
        while True:
            fn = self._jobs.get()
            try:
                fn()
            except Exception:  # jobs report their own errors; the worker survives
                import traceback
                traceback.print_exc()


class WorkerPool(object):
    """A fixed set of workers, grown lazily to the largest size ever asked for."""

    def __init__(self, name):
        self._name = name
        self._workers = []
        self._lock = threading.Lock()

    def workers(self, count):
        with self._lock:
            while len(self._workers) < count:
                self._workers.append(Worker('%s-%d' % (self._name, len(self._workers))))
            return self._workers[:count]
