"""An STS3215 emulator served from a process of its own, driven from this one as an in-process one is.

    with Sts3215EmulatorProcess(tmp_path / "ttyLEADER") as bus:   # same options as Sts3215Emulator
        bus.move_by_hand(1, 3000)
        bus.packet_listeners.append(lambda packet, now: ...)     # run here, stamped in the child

An emulator's serving thread needs the interpreter lock before it can answer. In a process whose other
threads run Python (an rclpy executor taking images and joint states, a benchmark's subscribers), it
waits its turn: with one such thread, pings took 44 ms at the median on a busy machine, against
microseconds for a servo. Here the emulator runs alone in a child process, all of whose threads are real-time when permitted,
and answers at once.
Calls go to the child over a socket pair and return its answer; listeners run in this process on a
thread of their own, with the child's timestamps (CLOCK_MONOTONIC is the machine's, so they compare
with this process's). `servo()` is not offered (its object lives in the child). stop() ends the
child and keeps its servos here: they answer the API until a later start() hands them to a new child.
"""

import os
import queue
import socket
import subprocess
import sys
import threading
import time
from collections import Counter
from multiprocessing.connection import Connection
from pathlib import Path

from joshua_runtime.emulators.realtime import raise_to_realtime_priority
from joshua_runtime.emulators.sts3215 import (
    POLL_INTERVAL_S,
    PacketListener,
    Sts3215Emulator,
    WriteListener,
)

START_TIMEOUT_S = 10.0  # the child imports the emulator and creates the pty
STOP_TIMEOUT_S = 2.0  # then it is killed


class EmulatorProcessError(RuntimeError):
    """The child serving the emulator did not start or stopped answering."""


class Sts3215EmulatorProcess:
    """Sts3215Emulator(link, **options) in a child process; its in-process API, forwarded."""

    def __init__(self, link: str | os.PathLike, ids=None, **options):
        self.link = Path(link)
        self._options = options if ids is None else {**options, "ids": list(ids)}
        self.write_listeners: list[WriteListener] = []
        self.packet_listeners: list[PacketListener] = []
        self._child: subprocess.Popen | None = None
        self._commands: Connection | None = None
        self._calls = threading.Lock()
        self._event_arrived = threading.Condition()
        self.device_name: str | None = None
        self._unplugged: Sts3215Emulator | None = None  # the servos between stop() and start()

    # --- lifecycle -------------------------------------------------------------------------
    def start(self) -> "Sts3215EmulatorProcess":
        if self._child is not None:
            return self
        commands, child_commands = socket.socketpair()
        events, child_events = socket.socketpair()
        fds = (child_commands.fileno(), child_events.fileno())
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(path for path in sys.path if path)}
        self._child = subprocess.Popen(
            [sys.executable, "-m", __name__, *map(str, fds)], pass_fds=fds, env=env, stdin=subprocess.DEVNULL
        )
        child_commands.close()
        child_events.close()
        self._commands = Connection(commands.detach())
        servos = self._unplugged.snapshot() if self._unplugged else None
        self._commands.send((str(self.link), self._options, servos))
        if not self._commands.poll(START_TIMEOUT_S):
            self.stop()
            raise EmulatorProcessError(f"the emulator process for {self.link} did not start")
        ok, answer = self._commands.recv()
        if not ok:
            self.stop()
            raise answer
        self.device_name, self._unplugged = answer, None
        threading.Thread(target=self._dispatch_events, args=(Connection(events.detach()),), daemon=True).start()
        return self

    def stop(self) -> None:
        """End the child (the pty goes with it, as when an adapter is unplugged)."""
        if self._child is None:
            return
        servos = None
        try:
            self._commands.send(None)
            if self._commands.poll(STOP_TIMEOUT_S):
                servos = self._commands.recv()
        except (EOFError, OSError):
            pass
        try:
            self._child.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self._child.kill()
            self._child.wait()
        self._commands.close()
        self._child, self._commands, self.device_name = None, None, None
        if servos is not None:
            self._unplugged = Sts3215Emulator(self.link, **self._options)
            self._unplugged.restore(servos)

    def __enter__(self) -> "Sts3215EmulatorProcess":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # --- the in-process API, forwarded ------------------------------------------------------
    def _call(self, name: str, *args):
        if self._commands is None:
            if self._unplugged is None:
                raise EmulatorProcessError(f"the emulator for {self.link} has not started")
            value = getattr(self._unplugged, name)
            return value(*args) if callable(value) else value
        with self._calls:
            try:
                self._commands.send((name, args))
                ok, result = self._commands.recv()
            except (EOFError, OSError):
                raise EmulatorProcessError(f"the emulator process for {self.link} is gone") from None
        if not ok:
            raise result
        return result

    @property
    def ids(self) -> list[int]:
        return self._call("ids")

    @property
    def stats(self) -> Counter:
        """A copy of the child's counters."""
        return self._call("stats")

    @property
    def serving_thread_id(self) -> int | None:
        return self._call("serving_thread_id")

    def move_by_hand(self, servo_id: int, position: float) -> None:
        self._call("move_by_hand", servo_id, position)

    def turn_shaft(self, servo_id: int, encoder_ticks: float) -> None:
        self._call("turn_shaft", servo_id, encoder_ticks)

    def position(self, servo_id: int) -> int:
        return self._call("position", servo_id)

    def read_register(self, servo_id: int, name: str) -> int:
        return self._call("read_register", servo_id, name)

    def write_register(self, servo_id: int, name: str, value: int) -> None:
        self._call("write_register", servo_id, name, value)

    def set_sensor(self, servo_id: int, name: str, value: int) -> None:
        self._call("set_sensor", servo_id, name, value)

    def inject_error(self, servo_id: int, bits: int) -> None:
        self._call("inject_error", servo_id, bits)

    def drop_next_replies(self, count: int) -> None:
        self._call("drop_next_replies", count)

    def corrupt_next_replies(self, count: int) -> None:
        self._call("corrupt_next_replies", count)

    def wait_until(self, predicate, timeout_s: float) -> bool:
        """Wait until `predicate()` holds, re-checked after every packet the child reports and every poll."""
        deadline = time.monotonic() + timeout_s
        while not predicate():
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return False
            with self._event_arrived:
                self._event_arrived.wait(min(remaining, POLL_INTERVAL_S))
        return True

    def _dispatch_events(self, events: Connection) -> None:
        with events:
            while True:
                try:
                    kind, event = events.recv()
                except (EOFError, OSError):
                    return
                for listener in list(self.write_listeners if kind == "write" else self.packet_listeners):
                    listener(*event)
                with self._event_arrived:
                    self._event_arrived.notify_all()


def _forward(outbox: queue.SimpleQueue, events: Connection) -> None:
    """Send the serving thread's events on, so that it never waits on the socket itself."""
    while True:
        try:
            events.send(outbox.get())
        except OSError:
            return


def serve_child(commands: Connection, events: Connection) -> None:
    """The child's side: build the emulator from the first message, then run each call until None.

    Every thread of the child runs at the serving thread's real-time priority (threads inherit it): one
    preempted while it holds the interpreter lock would hold up the serving thread's next reply.
    """
    raise_to_realtime_priority()
    link, options, servos = commands.recv()
    try:
        emulator = Sts3215Emulator(link, **options)
        if servos is not None:
            emulator.restore(servos)
        emulator.start()
    except Exception as exc:  # noqa: BLE001 - handed to the parent, which raises it
        commands.send((False, exc))
        return
    outbox = queue.SimpleQueue()
    emulator.write_listeners.append(lambda *event: outbox.put(("write", event)))
    emulator.packet_listeners.append(lambda *event: outbox.put(("packet", event)))
    threading.Thread(target=_forward, args=(outbox, events), daemon=True).start()
    commands.send((True, emulator.device_name))
    try:
        while (request := commands.recv()) is not None:
            name, args = request
            try:
                value = getattr(emulator, name)
                commands.send((True, value(*args) if callable(value) else value))
            except Exception as exc:  # noqa: BLE001 - handed to the caller, which raises it
                commands.send((False, exc))
        emulator.stop()
        commands.send(emulator.snapshot())
    except (EOFError, OSError):
        emulator.stop()  # the parent is gone


if __name__ == "__main__":
    serve_child(Connection(int(sys.argv[1])), Connection(int(sys.argv[2])))
