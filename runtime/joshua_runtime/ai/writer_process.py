"""The recorder's EpisodeWriter in a process of its own, so the node is ready before LeRobot is even imported.

Importing LeRobot (torch, datasets, torchvision) takes seconds: 3 s of CPU on an idle 2-core machine,
three or four times that under load. The node starts this process, announces itself ready and records
at once; frames wait in a queue of the node (and in the pipe) until the process has imported LeRobot,
then the process writes them with LeRobot's own LeRobotDataset exactly as the node would have. The
node's Python process never imports torch, so its ROS thread keeps its timing while LeRobot loads.

    node  --commands (writer_channel: configure, start, frame, stop, discard, undo, close)-->  process
    node  <--events (log lines, episode events, the error that ended the writer)------  process

The process ignores SIGINT and SIGTERM (the supervisor signals the whole process group), from its start
on (they are blocked until it ignores them): the node saves the episode in progress by sending `close`,
and the process ends once it is saved. It dies with
the node (PR_SET_PDEATHSIG, and at the end of its command pipe), leaving the episode in progress to
the staging directory that the next start recovers, exactly as a killed node would.
"""

import contextlib
import os
import queue
import signal
import subprocess
import sys
import threading
import time

from joshua_runtime.ai import writer_channel
from joshua_runtime.errors import DataLostError, JoshuaError, SettingsError
from joshua_runtime.notify import Notifier
from joshua_runtime.process_end import die_with_parent, end_process

ERRORS = {cls.__name__: cls for cls in (JoshuaError, SettingsError, DataLostError)}
COMMANDS = {
    "configure": "configure",
    "start": "start_episode",
    "frame": "add_frame",
    "stop": "end_episode",
    "discard": "discard_episode",
    "undo": "undo_last_episode",
}
# How long closing waits for a process still importing LeRobot to save the frames recorded meanwhile
# (a bound for a process that hangs; under the supervisor its SIGINT grace comes first).
LOAD_WAIT_AT_CLOSE_S = 120.0
EXIT_PARENT_GONE = 1
LOG_LEVELS = ("debug", "info", "warning", "error")
STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM}


class WriterProcess:
    """EpisodeWriter's interface (commands, `error`, `on_event`) over a child process that runs one."""

    def __init__(self, output_directory: str, fps: int, robot_type: str, use_videos: bool, log, on_event):
        self.log = log
        self.on_event = on_event
        self.error: BaseException | None = None
        self.started_s = time.monotonic()
        self._frames_sent = 0  # frames of the episode in progress handed to the process
        self._frames_total = 0  # frames handed to the process since it started
        self._closed = threading.Event()
        self.opened = threading.Event()
        commands_read, commands_write = os.pipe()
        events_read, events_write = os.pipe()
        # Blocked from before its exec until it ignores them: a stop signal to the node's process group as the
        # process's interpreter starts then waits for it, and is dropped, instead of killing it.
        unblocked = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
        try:
            self.process = subprocess.Popen(
                [sys.executable, "-m", __name__, str(commands_read), str(events_write)],
                pass_fds=(commands_read, events_write),
                stdin=subprocess.DEVNULL,
            )
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, unblocked)
        os.close(commands_read)
        os.close(events_write)
        self._commands = writer_channel.Sender(os.fdopen(commands_write, "wb"))
        self._events = os.fdopen(events_read, "rb")
        self._outbox: queue.Queue = queue.Queue()
        settings = {
            "output_directory": output_directory,
            "fps": fps,
            "robot_type": robot_type,
            "use_videos": use_videos,
        }
        self._outbox.put(("open", settings, None))
        self._sender = threading.Thread(target=self._send_all, name="writer-sender", daemon=True)
        self._receiver = threading.Thread(target=self._receive_all, name="writer-events", daemon=True)
        self._sender.start()
        self._receiver.start()

    # EpisodeWriter's commands, called from the ROS thread: queued, never blocking it.
    def configure(self, features: dict) -> None:
        self._outbox.put(("configure", features, None))

    def start_episode(self, task: str) -> None:
        self._frames_sent = 0
        self._outbox.put(("start", task, None))

    def add_frame(self, frame: dict) -> None:
        self._frames_sent += 1
        self._frames_total += 1
        self._outbox.put(("frame", None, frame))

    def end_episode(self) -> None:
        self._outbox.put(("stop", None, None))

    def discard_episode(self) -> None:
        self._outbox.put(("discard", None, None))

    def undo_last_episode(self) -> None:
        self._outbox.put(("undo", None, None))

    def close(self, notifier: Notifier | None = None) -> None:
        """Send every queued command and `close`, then wait until the process has saved and exited.

        A process still importing LeRobot is stopped at once when no frame was recorded, else waited for
        (at most LOAD_WAIT_AT_CLOSE_S), so that the frames recorded meanwhile are saved; the node's process
        manager (`notifier`) is asked for more time meanwhile, as that wait may outlast its SIGINT grace."""
        waiting = not self.opened.is_set() and self.error is None and self._frames_total
        why = f"saving {self._frames_total} frames: the dataset writer is still loading LeRobot"
        with notifier.more_time_to_stop(why) if waiting and notifier else contextlib.nullcontext():
            self._close()

    def _close(self) -> None:
        if not self.opened.is_set() and self.error is None:
            if self._frames_total:
                self.log.info(
                    f"saving the {self._frames_total} frames recorded so far waits for the dataset writer, "
                    "still loading LeRobot"
                )
            if not self._frames_total or not self.opened.wait(LOAD_WAIT_AT_CLOSE_S):
                self.process.kill()
                self._closed.set()
                if self._frames_total:
                    self.error = DataLostError(
                        f"{self._frames_total} frames lost: the dataset writer had not loaded LeRobot "
                        f"{LOAD_WAIT_AT_CLOSE_S:g} s after the recorder was stopped"
                    )
        self._outbox.put(("close", None, None))
        self._sender.join()
        self._receiver.join()
        self.process.wait()
        self._events.close()

    def _send_all(self) -> None:
        try:
            while True:
                kind, data, arrays = self._outbox.get()
                self._commands.send(kind, data, arrays)
                if kind == "close":
                    break
        except (BrokenPipeError, ValueError):  # the process is gone: the receiver reports why
            pass
        finally:
            try:
                self._commands.stream.close()
            except OSError:
                pass

    def _receive_all(self) -> None:
        while (message := writer_channel.read(self._events)) is not None:
            kind, data, _arrays = message
            if kind == "log":
                getattr(self.log, data["level"])(data["text"])
            elif kind == "event":
                event = data.pop("event")
                if event == "opened":
                    data["after_s"] = time.monotonic() - self.started_s
                    self.opened.set()
                self.on_event(event, **data)
            elif kind == "error":
                self.error = ERRORS.get(data["type"], JoshuaError)(data["message"])
                self.opened.set()  # nothing more to wait for
            elif kind == "closed":
                self._closed.set()
        if not self._closed.is_set() and self.error is None:
            code = self.process.wait()
            lost = f"; the episode of {self._frames_sent} frames in progress is lost" if self._frames_sent else ""
            self.error = (DataLostError if self._frames_sent else JoshuaError)(
                f"the dataset writer process ended unexpectedly (exit code {code}){lost}"
            )
            self.opened.set()  # a stop waiting for it to load LeRobot has nothing more to wait for
            self.on_event("failed", message=str(self.error))


class _ChannelLog:
    """The logger EpisodeWriter writes to, in the process: each line goes to the node, which logs it."""

    def __init__(self, sender: writer_channel.Sender):
        self.sender = sender

    def __getattr__(self, level: str):
        if level not in LOG_LEVELS:
            raise AttributeError(level)
        return lambda text, **_options: self.sender.send("log", {"level": level, "text": str(text)})


def main(argv: list[str]) -> int:
    """The process: open an EpisodeWriter as the node asks, apply its commands until `close`."""
    for number in STOP_SIGNALS:
        signal.signal(number, signal.SIG_IGN)  # a stop signal pending since the start is dropped here
    signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
    parent = os.getppid()
    die_with_parent()
    if os.getppid() != parent:
        return EXIT_PARENT_GONE
    commands = os.fdopen(int(argv[0]), "rb")
    sender = writer_channel.Sender(os.fdopen(int(argv[1]), "wb"))
    opening = writer_channel.read(commands)
    if opening is None or opening[0] != "open":
        return EXIT_PARENT_GONE
    made = threading.Event()
    holder = []

    def on_event(event: str, **details) -> None:
        if event == "failed":
            made.wait()
            error = holder[0].error
            sender.send("error", {"type": type(error).__name__, "message": str(error)})
        sender.send("event", {"event": event, **details})

    try:
        from joshua_runtime.ai.episode_writer import EpisodeWriter

        holder.append(EpisodeWriter(**opening[1], log=_ChannelLog(sender), on_event=on_event))
    except BaseException as exc:  # LeRobot missing or broken: the node reports it
        sender.send("error", {"type": "JoshuaError", "message": f"cannot open the dataset writer: {exc}"})
        return 1
    finally:
        made.set()
    writer = holder[0]
    while (message := writer_channel.read(commands)) is not None:
        kind, data, arrays = message
        if kind == "close":
            writer.close()
            sender.send("closed")
            return 0
        method = getattr(writer, COMMANDS[kind])
        if kind == "frame":
            method(arrays)
        elif kind == "configure":
            method({key: dict(feature, shape=tuple(feature["shape"])) for key, feature in data.items()})
        elif data is None:
            method()
        else:
            method(data)
    os._exit(EXIT_PARENT_GONE)  # the node is gone without closing: as if killed with it


if __name__ == "__main__":
    end_process(main(sys.argv[1:]))  # without LeRobot's teardown, seconds of the recorder's stop
