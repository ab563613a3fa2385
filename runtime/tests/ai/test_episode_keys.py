"""`joshua-episode keys` in a terminal (a pty): lerobot-record's keys drive a real recorder.

Right arrow saves the episode and (the reset period being long) starts the next one when pressed again
during the reset; left arrow drops the episode in progress to record it again; Esc ends the reset and
the key session. The terminal is given back in the mode it had.
"""

import os
import re
import signal
import subprocess
import termios
import threading
import time

from ai_support import NodeProcess
from test_ai_recorder import Sensors, load
from test_episode_workflow import EPISODE, FIRST_FRAME, LONG_RESET_S, RECORDER, settings

RIGHT, LEFT, ESC = b"\x1b[C", b"\x1b[D", b"\x1b"
SCREEN_TIMEOUT_S = 90.0
EXIT_TIMEOUT_S = 30.0


class Terminal:
    """`joshua-episode keys` on the slave side of a pty; what it writes is collected from the master side."""

    def __init__(self, env: dict):
        self.master, self.slave = os.openpty()
        self.mode = termios.tcgetattr(self.slave)  # before the command can change it
        self.process = subprocess.Popen(
            [EPISODE, "keys", "--node", RECORDER],
            stdin=self.slave,
            stdout=self.slave,
            stderr=self.slave,
            env=dict(env, TERM="xterm"),
            start_new_session=True,
        )
        self.screen = b""
        self.condition = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while True:
            try:
                data = os.read(self.master, 4096)
            except OSError:
                return
            if not data:
                return
            with self.condition:
                self.screen += data
                self.condition.notify_all()

    def wait_for(self, pattern: str, after: int = 0) -> re.Match:
        """The first match of `pattern` in the output from byte `after` on."""
        regex = re.compile(pattern.encode())
        deadline = time.monotonic() + SCREEN_TIMEOUT_S
        with self.condition:
            while not (found := regex.search(self.screen, after)):
                remaining = deadline - time.monotonic()
                assert remaining > 0 and self.process.poll() is None, f"no {pattern!r} in {self.screen!r}"
                self.condition.wait(min(remaining, 0.5))
            return found

    def press(self, keys: bytes) -> int:
        with self.condition:
            mark = len(self.screen)
        os.write(self.master, keys)
        return mark

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        os.close(self.slave)
        os.close(self.master)


def test_arrows_and_escape_drive_the_recorder_like_lerobot_record(tmp_path, ai_env, ros_peer, lerobot_offline):
    output = tmp_path / "dataset"
    sensors = Sensors(ros_peer)
    node = NodeProcess(settings(output, reset_time_s=LONG_RESET_S), ai_env)
    terminal = Terminal(ai_env)
    try:
        node.wait_for(FIRST_FRAME)
        terminal.wait_for(r"-> next episode")
        terminal.wait_for(r"recording episode 0 \(task: test_arm\): [\d.]+ s, [1-9]\d* frames")
        saved = terminal.wait_for(r"saved episode 0 \((\d+) frames\)", terminal.press(RIGHT))
        terminal.wait_for(r"resetting, [\d.]+ s left before episode 1", saved.end())
        sensors.set_phase(1)
        node_mark = node.count()
        terminal.wait_for(r"episode started \(task: test_arm\)", terminal.press(RIGHT))
        node.wait_for(FIRST_FRAME, after=node_mark)
        terminal.wait_for(r"dropped the episode in progress \(\d+ frames\); resetting", terminal.press(LEFT))
        terminal.wait_for(r"reset period ended; no episode recording", terminal.press(ESC))
        assert terminal.process.wait(EXIT_TIMEOUT_S) == 0
        assert termios.tcgetattr(terminal.slave) == terminal.mode  # cbreak mode undone
        assert node.stop(signal.SIGINT) == 0
    finally:
        terminal.close()
        node.kill()
    dataset = load(output)
    assert dataset.meta.total_episodes == 1 and len(dataset) == int(saved.group(1))


def test_keys_need_a_terminal(ai_env):
    result = subprocess.run(
        [EPISODE, "keys", "--node", RECORDER], env=ai_env, stdin=subprocess.DEVNULL, capture_output=True, text=True
    )
    assert result.returncode == 2
    assert result.stderr == "joshua-episode: error: keys reads the keyboard of a terminal; stdin is not one\n"
