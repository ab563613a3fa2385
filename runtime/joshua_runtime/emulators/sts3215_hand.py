"""A hand on the joints of an emulated STS3215 bus, moved by commands read one per line (stdin or a script).

    turn ID TICKS                     put servo ID's shaft at TICKS at once
    sweep ID FROM TO [SECONDS]        turn it steadily from FROM to TO (default 1 s), as a hand sweeps a joint
    wait SECONDS                      hold still (for scripts)

TICKS are the encoder's raw reading, 0-4095, before the servo's Homing_Offset: where the hand puts the
shaft, whatever offset a calibration writes meanwhile. Each command is answered on the output when it
is done (`hand: done LINE`) or refused (`hand: error: ...`), so a program driving the hand knows when a
motion is over. Blank lines and lines starting with `#` are skipped.
"""

import time
from collections.abc import Callable
from typing import TextIO

from joshua_runtime.drivers.sts3215_table import MAX_TICK

HAND_STEP_S = 0.01  # a sweep moves the shaft this often
DEFAULT_SWEEP_S = 1.0
USAGE = "commands: turn ID TICKS | sweep ID FROM TO [SECONDS] | wait SECONDS"


class HandError(ValueError):
    """A command the hand cannot follow (unknown word, bad number, no such servo)."""


def _number(text: str, what: str, low: float, high: float | None = None) -> float:
    try:
        value = float(text)
    except ValueError:
        raise HandError(f"{what} must be a number, got {text!r}") from None
    if not low <= value <= (high if high is not None else value):
        raise HandError(f"{what} must be {low:g}-{high:g}" if high is not None else f"{what} must be >= {low:g}")
    return value


def _servo(emulator, text: str) -> int:
    try:
        servo_id = int(text)
    except ValueError:
        raise HandError(f"servo id must be an integer, got {text!r}") from None
    if servo_id not in emulator.ids:
        raise HandError(f"no servo with id {servo_id} on this bus (ids {','.join(map(str, emulator.ids))})")
    return servo_id


def follow(emulator, words: list[str], should_stop: Callable[[], bool]) -> None:
    """Carry out one command (its words) on `emulator`; a sweep or wait ends early once should_stop()."""
    verb, arguments = words[0], words[1:]
    if verb == "turn" and len(arguments) == 2:
        servo_id = _servo(emulator, arguments[0])
        emulator.turn_shaft(servo_id, _number(arguments[1], "TICKS", 0, MAX_TICK))
    elif verb == "sweep" and len(arguments) in (3, 4):
        servo_id = _servo(emulator, arguments[0])
        start, end = (_number(text, what, 0, MAX_TICK) for text, what in zip(arguments[1:3], ("FROM", "TO")))
        seconds = _number(arguments[3], "SECONDS", 0) if len(arguments) == 4 else DEFAULT_SWEEP_S
        began = time.monotonic()
        while not should_stop():
            fraction = min(1.0, (time.monotonic() - began) / seconds) if seconds else 1.0
            emulator.turn_shaft(servo_id, start + (end - start) * fraction)
            if fraction >= 1.0:
                break
            time.sleep(HAND_STEP_S)
    elif verb == "wait" and len(arguments) == 1:
        deadline = time.monotonic() + _number(arguments[0], "SECONDS", 0)
        while not should_stop() and time.monotonic() < deadline:
            time.sleep(min(HAND_STEP_S, max(0.0, deadline - time.monotonic())))
    else:
        raise HandError(f"cannot follow {' '.join(words)!r}; {USAGE}")


def run_hand(emulator, commands: TextIO, out: TextIO, should_stop: Callable[[], bool]) -> None:
    """Follow every command line of `commands` until its end or should_stop(), answering each on `out`."""
    for line in commands:
        if should_stop():
            return
        words = line.split()
        if not words or words[0].startswith("#"):
            continue
        try:
            follow(emulator, words, should_stop)
        except HandError as exc:
            print(f"hand: error: {exc}", file=out, flush=True)
        else:
            print(f"hand: done {' '.join(words)}", file=out, flush=True)
