"""How a node process is told to stop: a SIGINT/SIGTERM handler that is cheap to import.

It lives apart from node.py, which imports rclpy (a tenth of a second or more), so that a process
can install it before that import: a signal during the import then ends the node cleanly too.
"""

import os
import signal
import threading
from collections.abc import Callable


class StopRequested(BaseException):
    """Raised by the signal handler while a node is still starting (importing, opening devices).

    A BaseException, so that no `except Exception` in start-up code swallows it.
    """


class StopSignal:
    """SIGINT/SIGTERM handler: sets `event`; while `starting`, also abandons start-up at once."""

    def __init__(self):
        self.event = threading.Event()
        self.starting = True

    def install(self) -> "StopSignal":
        signal.signal(signal.SIGINT, self)
        signal.signal(signal.SIGTERM, self)
        return self

    def __call__(self, signum, _frame) -> None:
        self.event.set()
        if self.starting:
            raise StopRequested(signum)


class SignalWake:
    """Calls `wake` from a thread of its own as soon as a signal arrives. A Python signal handler runs only once
    the main thread is back in Python; while that thread waits in native code (rcl_wait), `wake` can end the wait,
    so the handler runs at once instead of at the wait's timeout. Uses the interpreter's wakeup descriptor,
    which its C-level handler writes to; main thread only."""

    def __init__(self, wake: Callable[[], None]):
        self.wake = wake
        self.closing = False
        self.read_end, self.write_end = os.pipe()
        os.set_blocking(self.write_end, False)
        self.previous = signal.set_wakeup_fd(self.write_end, warn_on_full_buffer=False)
        self.thread = threading.Thread(target=self._forward, name="signal-wake", daemon=True)
        self.thread.start()

    def _forward(self) -> None:
        while os.read(self.read_end, 64) and not self.closing:
            self.wake()

    def close(self) -> None:
        """Stop waking and give the wakeup descriptor back. The thread is told by a byte of its own, not by the
        pipe's end: a child forked meanwhile may hold the write end open."""
        signal.set_wakeup_fd(self.previous, warn_on_full_buffer=False)
        self.closing = True
        try:
            os.write(self.write_end, b"\0")
        except BlockingIOError:  # full of signals' bytes: the thread reads them and sees `closing`
            pass
        self.thread.join()
        os.close(self.read_end)
        os.close(self.write_end)
