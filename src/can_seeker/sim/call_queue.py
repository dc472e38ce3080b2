"""Run callables on the one thread that owns a resource (pybullet is not thread-safe).

Callbacks run on their own threads: they :meth:`CallQueue.post` a function, or
:meth:`CallQueue.call` it and wait, while the owner thread executes every pending call with
:meth:`CallQueue.run_pending` between its own steps.
"""
import queue
import threading
from typing import Any, Callable


class CallQueue:
    """Calls queued by any thread, executed by the owner thread in arrival order."""

    def __init__(self):
        self._pending = queue.Queue()

    def post(self, function: Callable[[], Any]):
        """Queue ``function`` without waiting for it (its result and errors are dropped)."""
        self._pending.put((function, threading.Event(), {}))

    def call(self, function: Callable[[], Any], timeout_s: float) -> Any:
        """Queue ``function``, wait for the owner thread to run it and return its result.

        Re-raises the function's exception; TimeoutError when the owner does not run it within
        ``timeout_s`` (wall clock).
        """
        done = threading.Event()
        outcome = {}
        self._pending.put((function, done, outcome))
        if not done.wait(timeout_s):
            raise TimeoutError('the simulation did not run the request within %.1f s' % timeout_s)
        if 'error' in outcome:
            raise outcome['error']
        return outcome['result']

    def run_pending(self):
        """Run every queued call (owner thread only)."""
        while True:
            try:
                function, done, outcome = self._pending.get_nowait()
            except queue.Empty:
                return
            try:
                outcome['result'] = function()
            except Exception as error:  # handed back to the caller's thread
                outcome['error'] = error
            done.set()
