"""Work the scene does off the main thread: the precompute of new tables, the quick view's table of the orders
above the first.

A :class:`BackgroundJob` is made when a change needs the work and starts when the scene draws the frame that
follows the change (or when someone waits for it), so that frame has the cores to itself; a job superseded before
that frame never runs. A job can run at a lower CPU priority where a thread can have its own (Linux), so the
frames drawn while it runs keep most of the cores (on a software renderer the frames are the CPU's work as
well; the change to the first frame in docs/benchmarks.md, "Quick view"), without being starved by a window that
renders continuously (a playing sequence, a long drag).
"""
from __future__ import annotations

import os
import sys
import threading

#: The niceness of the background jobs' threads (Linux), the precompute's and the quick view's table's: against a
#: thread of niceness 0 such a thread gets about a tenth of a core both want (the kernel's weights 110 and 1024).
BACKGROUND_NICENESS = 10


def _set_niceness(niceness):
    """Give the calling thread this niceness, where the system has per-thread priorities (Linux)."""
    if niceness and sys.platform.startswith("linux"):
        try:
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), niceness)
        except OSError:                       # not permitted here: the job runs at the process's priority
            pass


class BackgroundJob:
    """``work()`` in a daemon thread at ``niceness`` (0: the process's priority), started by :meth:`start` (once;
    :meth:`join` starts it too). ``result`` holds what ``work`` returned and ``error`` the exception it raised,
    once :attr:`done`."""

    def __init__(self, work, niceness=0):
        self.result = self.error = None
        self._work, self._niceness = work, niceness
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
        _set_niceness(self._niceness)
        try:
            self.result = self._work()
        except Exception as exc:              # the caller reads it from ``error`` and keeps what it shows
            self.error = exc
