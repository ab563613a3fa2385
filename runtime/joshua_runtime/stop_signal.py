"""How a node process is told to stop: a SIGINT/SIGTERM handler that is cheap to import.

It lives apart from node.py, which imports rclpy (a tenth of a second or more), so that a process
can install it before that import: a signal during the import then ends the node cleanly too.
"""

import signal
import threading


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
