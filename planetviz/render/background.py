"""Work the scene does off the main thread: the precompute of new tables, the quick view's table of the orders
above the first.

A :class:`BackgroundJob` is made when a change needs the work and starts when the scene draws the frame that
follows the change (or when someone waits for it), so that frame has the cores to itself; a job superseded before
that frame never runs. It runs at the lowest CPU priority where a thread can have its own (Linux), so the frames
drawn while it runs keep the cores too (on a software renderer the frames are the CPU's work as well; the change
to the first frame in docs/benchmarks.md, "Quick view").
"""
from __future__ import annotations

import os
import sys
import threading

#: The niceness of a background job's thread (Linux; elsewhere it runs at the process's priority).
BACKGROUND_NICENESS = 19


def _lower_priority():
    """Give the calling thread the lowest CPU priority, where the system has per-thread priorities (Linux)."""
    if sys.platform.startswith("linux"):
        try:
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), BACKGROUND_NICENESS)
        except OSError:                       # not permitted here: the job runs at the process's priority
            pass


class BackgroundJob:
    """``work()`` in a daemon thread at the lowest priority, started by :meth:`start` (once; :meth:`join` starts it
    too). ``result`` holds what ``work`` returned and ``error`` the exception it raised, once :attr:`done`."""

    def __init__(self, work):
        self.result = self.error = None
        self._work = work
        self._thread = threading.Thread(target=self._run, daemon=True)
        self.started = False

    def start(self):
        if not self.started:
            self.started = True
            self._thread.start()

    @property
    def done(self):
        """True once the work has finished (or failed)."""
        return self.started and not self._thread.is_alive()

    def join(self, timeout=None):
        """Start the work if it has not started, and wait for it (at most ``timeout`` seconds)."""
        self.start()
        self._thread.join(timeout)

    def _run(self):
        _lower_priority()
        try:
            self.result = self._work()
        except Exception as exc:              # the caller reads it from ``error`` and keeps what it shows
            self.error = exc
