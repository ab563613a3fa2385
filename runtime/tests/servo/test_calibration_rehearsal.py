"""Calibration rehearsed end to end without hardware.

`joshua-emulate sts3215 --hand -` serves the bus and moves its joints as a person would, by commands on
its stdin; `joshua-servo calibrate` runs in its own process, read and answered as a terminal user would.
A joint left still is named, with the command that redoes just it, and the other joints are saved.
"""

import json
import queue
import shlex
import signal
import subprocess
import sys
import threading

import pytest
from servo_helpers import SO100_IDS, SO100_JOINTS

pytestmark = pytest.mark.process

# Encoder ticks of each joint at its homing pose, and its end stops in ticks from there.
MOUNTS = dict(zip(SO100_JOINTS, [1900, 2200, 1700, 2400, 3000, 1000]))
STOPS = {
    "shoulder_pan": (-1200, 1250),
    "shoulder_lift": (-1100, 1000),
    "elbow_flex": (-1050, 1100),
    "wrist_flex": (-1000, 1080),
    "gripper": (-15, 1150),
}
HOMED_TICK = 2047  # what the homing pose reads once homed
HOLD_S = 0.3  # at each end stop, for the 20 Hz sampling to see it
SWEEP_S = 0.5
LINE_TIMEOUT_S = 30.0
EXIT_TIMEOUT_S = 30.0
CALIBRATE = [sys.executable, "-m", "joshua_runtime.servo_tools.cli", "calibrate"]


def lines_of(stream) -> queue.Queue:
    """The lines of `stream` as they come, read by a thread."""
    lines: queue.Queue = queue.Queue()

    def read() -> None:
        for line in stream:
            lines.put(line.rstrip("\n"))
        lines.put(None)

    threading.Thread(target=read, daemon=True).start()
    return lines


class Hand:
    """`joshua-emulate sts3215 --hand -` at `link`: the bus and the hand that moves its joints."""

    def __init__(self, link):
        self.process = subprocess.Popen(
            [sys.executable, "-m", "joshua_runtime.emulators.cli", "sts3215", "--link", str(link), "--hand", "-"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        self.lines = lines_of(self.process.stdout)
        banner = self.lines.get(timeout=LINE_TIMEOUT_S)
        assert banner and banner.startswith(f"sts3215: servos 1,2,3,4,5,6 on {link}"), banner

    def do(self, *commands: str) -> None:
        """Each command, waiting until the emulator says it is done."""
        for command in commands:
            self.process.stdin.write(command + "\n")
            self.process.stdin.flush()
            assert self.lines.get(timeout=LINE_TIMEOUT_S) == f"hand: done {command}"

    def close(self) -> None:
        self.process.send_signal(signal.SIGINT)
        assert self.process.wait(EXIT_TIMEOUT_S) == 0
        self.process.stdin.close()


def rehearse(hand: Hand, command: list[str], still: tuple[str, ...] = ()) -> tuple[int, list[str], str]:
    """Run `command`, doing what each prompt asks (but sweeping no joint of `still`) and pressing Enter.

    Returns the exit code, the lines printed and stderr."""
    process = subprocess.Popen(
        command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    transcript = []
    try:
        for line in process.stdout:
            transcript.append(line.rstrip())
            words = line.split()
            joint = words[1] if line.startswith(("Hold", "Move")) else None
            if line.startswith("Hold"):
                hand.do(f"turn {servo_id(joint)} {MOUNTS[joint]}")
            elif line.startswith("Move") and joint in still:
                hand.do(f"wait {HOLD_S}")
            elif line.startswith("Move"):
                low, high = (MOUNTS[joint] + stop for stop in STOPS[joint])
                hand.do(
                    f"turn {servo_id(joint)} {low}",
                    f"wait {HOLD_S}",
                    f"sweep {servo_id(joint)} {low} {high} {SWEEP_S}",
                    f"wait {HOLD_S}",
                )
            else:
                continue
            try:
                process.stdin.write("\n")
                process.stdin.flush()
            except BrokenPipeError:  # it ended early: its exit code and stderr say why
                break
    finally:
        try:
            process.stdin.close()
        except BrokenPipeError:
            pass
        code = process.wait(EXIT_TIMEOUT_S)
    return code, transcript, process.stderr.read()


def servo_id(joint: str) -> int:
    return SO100_IDS[SO100_JOINTS.index(joint)]


def assert_swept_ranges(saved: dict, joints) -> None:
    for joint in joints:
        low, high = STOPS[joint]
        assert (saved[joint]["range_min"], saved[joint]["range_max"]) == (HOMED_TICK + low, HOMED_TICK + high), joint
        assert saved[joint]["id"] == servo_id(joint)


def test_a_joint_left_still_is_named_the_others_are_saved_and_it_is_redone_alone(tmp_path):
    link, output = tmp_path / "ttyARM", tmp_path / "follower.json"
    hand = Hand(link)
    try:
        code, transcript, stderr = rehearse(
            hand, [*CALIBRATE, str(link), "--output", str(output)], still=("wrist_flex",)
        )
        assert code == 5, (transcript, stderr)
        assert "  wrist_flex did not move during its sweep: not saved; the other joints go on" in transcript
        assert transcript[-1] == f"calibration of 5 of 6 joints written to {output}; missing: wrist_flex"
        redo = f"joshua-servo calibrate {link} --robot so100 --role follower --output {output} --joints wrist_flex"
        assert stderr == (
            f"joshua-servo: error: wrist_flex did not move during its sweep; the other joints are saved in {output}. "
            f"Redo just it: {redo}\n"
        )
        first = json.loads(output.read_text())
        assert sorted(first) == sorted(set(SO100_JOINTS) - {"wrist_flex"})
        assert_swept_ranges(first, set(STOPS) - {"wrist_flex"})
        assert (first["wrist_roll"]["range_min"], first["wrist_roll"]["range_max"]) == (0, 4095)

        code, transcript, stderr = rehearse(hand, [*CALIBRATE, *shlex.split(redo)[2:]])
        assert code == 0, (transcript, stderr)
        assert transcript[0].startswith("Hold wrist_flex at its homing pose")
        assert not any(line.startswith(("Hold", "Move")) and "wrist_flex" not in line for line in transcript)
        assert transcript[-1] == f"calibration written to {output}"
        second = json.loads(output.read_text())
        assert list(second) == SO100_JOINTS
        assert {joint: entry for joint, entry in second.items() if joint != "wrist_flex"} == first
        assert_swept_ranges(second, ["wrist_flex"])
    finally:
        hand.close()


def test_a_full_rehearsal_saves_all_six_joints(tmp_path):
    link, output = tmp_path / "ttyARM", tmp_path / "leader.json"
    hand = Hand(link)
    try:
        code, transcript, stderr = rehearse(hand, [*CALIBRATE, str(link), "--role", "leader", "--output", str(output)])
    finally:
        hand.close()
    assert (code, stderr) == (0, ""), transcript
    assert transcript[-1] == f"calibration written to {output}"
    saved = json.loads(output.read_text())
    assert list(saved) == SO100_JOINTS
    assert_swept_ranges(saved, STOPS)
    assert (saved["wrist_roll"]["range_min"], saved["wrist_roll"]["range_max"]) == (0, 4095)
