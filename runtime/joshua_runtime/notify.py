"""The sd_notify protocol, sending side: a node tells its process manager it is ready, alive or stopping.

systemd (`Type=notify`) and supervisor.py both hand a node `NOTIFY_SOCKET`, the address of a Unix
datagram socket (a path, or `@name` in the abstract namespace). Each message is one datagram of
newline-separated `KEY=VALUE` lines: `READY=1` once the node serves what it should, `STATUS=...` a
one-line description, `WATCHDOG=1` at least every half `WATCHDOG_USEC` while the node's loop runs,
`STOPPING=1` when it begins to stop, `EXTEND_TIMEOUT_USEC=N` while stopping takes longer than the manager's
grace (a save in progress): the manager waits N µs more before its SIGTERM. Without `NOTIFY_SOCKET` every call does nothing. Sending never
raises: a manager that went away must not take the node with it.
"""

import contextlib
import os
import socket
import threading
import time

SOCKET_VARIABLE = "NOTIFY_SOCKET"
WATCHDOG_USEC_VARIABLE = "WATCHDOG_USEC"
WATCHDOG_PID_VARIABLE = "WATCHDOG_PID"
# While a node asks for more time to stop, it asks for this much more every STOP_EXTENSION_ASK_S: five asks in
# each extension, so one that waits for the CPU for a few seconds on a loaded machine does not let it run out.
STOP_EXTENSION_S = 5.0
STOP_EXTENSION_ASK_S = 1.0


def socket_address(value: str) -> str | None:
    """The address `socket.sendto` takes for a NOTIFY_SOCKET value; None for forms not supported (vsock)."""
    if value.startswith("@") and len(value) > 1:
        return "\0" + value[1:]
    if value.startswith("/"):
        return value
    return None


def one_line(text: str) -> str:
    return " ".join(text.split())


class Notifier:
    """Sends notifications to one manager's socket; `watchdog_interval_s` is None when none is asked for."""

    def __init__(self, address: str | None, watchdog_interval_s: float | None = None):
        self.address = address
        self.watchdog_interval_s = watchdog_interval_s
        self.last_watchdog_s = None
        self._socket = None
        self._lock = threading.Lock()  # the loader thread of a node may announce while the loop pings

    @classmethod
    def from_environment(cls, environ=os.environ) -> "Notifier":
        """The manager's notifier; the variables are taken out of `environ`, so no child process
        of the node speaks for it."""
        value = environ.pop(SOCKET_VARIABLE, "")
        usec = environ.pop(WATCHDOG_USEC_VARIABLE, "")
        watchdog_pid = environ.pop(WATCHDOG_PID_VARIABLE, "")
        interval = None
        if usec.isdigit() and int(usec) > 0 and watchdog_pid in ("", str(os.getpid())):
            interval = int(usec) / 1e6
        return cls(socket_address(value) if value else None, interval)

    @property
    def enabled(self) -> bool:
        return self.address is not None

    def send(self, *assignments: str) -> bool:
        """Send `KEY=VALUE` lines in one datagram; False when there is no manager or it did not take it."""
        if self.address is None:
            return False
        data = "\n".join(assignments).encode("utf-8", "replace")
        with self._lock:
            try:
                if self._socket is None:
                    self._socket = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM | socket.SOCK_CLOEXEC)
                self._socket.sendto(data, self.address)
            except OSError:
                return False
        return True

    def ready(self, status: str) -> bool:
        return self.send("READY=1", f"STATUS={one_line(status)}")

    def status(self, status: str) -> bool:
        return self.send(f"STATUS={one_line(status)}")

    def stopping(self) -> bool:
        return self.send("STOPPING=1")

    @contextlib.contextmanager
    def more_time_to_stop(self, why: str):
        """While inside, ask the manager again and again for more time before it escalates the stop (SIGTERM)."""
        if self.address is None:
            yield
            return
        done = threading.Event()

        def ask() -> None:
            while True:
                self.send(f"EXTEND_TIMEOUT_USEC={int(STOP_EXTENSION_S * 1e6)}", f"STATUS={one_line(why)}")
                if done.wait(STOP_EXTENSION_ASK_S):
                    return

        asking = threading.Thread(target=ask, name="stop-extension", daemon=True)
        asking.start()
        try:
            yield
        finally:
            done.set()
            asking.join()

    def watchdog(self, now_s: float | None = None) -> bool:
        """Ping the watchdog when half its interval has passed since the last ping; True when pinged."""
        if self.watchdog_interval_s is None:
            return False
        now_s = time.monotonic() if now_s is None else now_s
        if self.last_watchdog_s is not None and now_s - self.last_watchdog_s < self.watchdog_interval_s / 2:
            return False
        self.last_watchdog_s = now_s
        return self.send("WATCHDOG=1")

    def close(self) -> None:
        with self._lock:
            if self._socket is not None:
                self._socket.close()
                self._socket = None
