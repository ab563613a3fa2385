"""The recorder's dataset writer process and the stop signals: a SIGINT to the node's process group as the writer's
interpreter starts does not kill it, and a writer that dies while still loading LeRobot does not hold the
recorder's stop.

The supervisor stops a node with SIGINT to its whole process group, the writer included; a robot stopped
right after it started catches the writer still starting its interpreter, before its own code runs.
"""

import os
import signal
import threading
import time

from ai_support import slow_lerobot_env

from joshua_runtime.ai.writer_process import WriterProcess
from joshua_runtime.errors import DataLostError

STARTING_S = 2.0  # how long the writer's interpreter spends in its site hook before the writer's own code
NEVER_S = 600.0
CLOSE_TIMEOUT_S = 30.0  # far less than the 120 s a stop waits for a writer still loading LeRobot
FRAMES = 3


class Log:
    def __init__(self):
        self.lines: list[str] = []

    def __getattr__(self, level: str):
        return lambda text, **_options: self.lines.append(f"{level}: {text}")


def slow_writer(tmp_path, monkeypatch, starting_s: float) -> WriterProcess:
    """A writer whose interpreter spends `starting_s` in its site hook and then never finishes importing LeRobot."""
    env = slow_lerobot_env(tmp_path, dict(os.environ), NEVER_S, starting_s)
    monkeypatch.setenv("PYTHONPATH", env["PYTHONPATH"])
    return WriterProcess(str(tmp_path / "dataset"), 30, "so100", False, Log(), lambda event, **_details: None)


def test_a_sigint_as_the_writers_interpreter_starts_does_not_kill_it(tmp_path, monkeypatch):
    writer = slow_writer(tmp_path, monkeypatch, STARTING_S)
    try:
        writer.process.send_signal(signal.SIGINT)  # the group's SIGINT, while the site hook runs
        time.sleep(STARTING_S * 2)
        assert writer.process.poll() is None, f"the writer ended with {writer.process.returncode}"
    finally:
        writer.close()  # no frame was recorded: the writer is stopped at once


def test_a_writer_that_dies_while_loading_lerobot_does_not_hold_the_stop(tmp_path, monkeypatch):
    writer = slow_writer(tmp_path, monkeypatch, 0.0)
    for _ in range(FRAMES):
        writer.add_frame({})
    writer.process.kill()
    closing = threading.Thread(target=writer.close, daemon=True)
    closing.start()
    closing.join(CLOSE_TIMEOUT_S)
    assert not closing.is_alive(), "closing waited for a writer that had died"
    assert isinstance(writer.error, DataLostError)
    assert str(writer.error).startswith("the dataset writer process ended unexpectedly (exit code -9)")
