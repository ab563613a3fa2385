"""`joshua-episode keys`: lerobot-record's keys in a terminal, sent to a running recorder as episode commands.

    ->   next      save the episode, reset, record the next one (during a reset: start it now)
    <-   rerecord  drop the episode in progress (or remove the one just saved) and record it again
    Esc  stop      save the episode in progress and end the session (this command then exits)
    q    quit without a command (so does Ctrl-C)

The terminal is put in cbreak mode (keys arrive without Enter, nothing is echoed) and given back as it
was. One status line, the episode's timer and frame count from the recorder's progress topic, is
redrawn in place; each answer of the recorder is printed on a line of its own.
"""

import os
import select
import sys
import termios
import time
import tty

from joshua_runtime.ai.episode_client import RecorderClient, describe

KEY_COMMANDS = {"right": "next", "left": "rerecord", "esc": "stop"}
SEQUENCES = {b"\x1b[C": "right", b"\x1bOC": "right", b"\x1b[D": "left", b"\x1bOD": "left"}
QUIT_KEYS = (b"q", b"Q")
ESCAPE = b"\x1b"
ESCAPE_WAIT_S = 0.05  # after a lone Esc byte, how long the rest of an arrow's sequence may take to arrive
READ_SLICE_S = 0.05
REDRAW_PERIOD_S = 0.25
ANSWER_TIMEOUT_S = 60.0
CLEAR_LINE = "\r\x1b[K"
HELP = "keys: -> next episode   <- re-record   Esc stop and quit   q quit"


def parse(data: bytes) -> list[str]:
    """The keys in a chunk of terminal input: "right", "left", "esc", "quit"; other bytes are ignored."""
    keys, i = [], 0
    while i < len(data):
        sequence = data[i : i + 3]
        if sequence in SEQUENCES:
            keys.append(SEQUENCES[sequence])
            i += 3
            continue
        byte = data[i : i + 1]
        if byte == ESCAPE:
            keys.append("esc")
        elif byte in QUIT_KEYS:
            keys.append("quit")
        i += 1
    return keys


def read_keys(fd: int) -> list[str]:
    """The keys typed since the last call (waits at most READ_SLICE_S)."""
    if not select.select([fd], [], [], READ_SLICE_S)[0]:
        return []
    data = os.read(fd, 64)
    while data.endswith(ESCAPE) and select.select([fd], [], [], ESCAPE_WAIT_S)[0]:
        data += os.read(fd, 64)  # the rest of an arrow's sequence, split across reads
    return parse(data) if data else ["quit"]


def run(node_name: str, domain: int | None, discovery_s: float) -> int:
    """The key loop; exit code 0 (quit, or Esc), 1 (the episode Esc stopped could not be saved), 3 (no recorder)."""
    from joshua_runtime.ai.episode_cli import EXIT_NO_RECORDER, EXIT_OK, EXIT_REFUSED, EXIT_USAGE, no_recorder

    fd = sys.stdin.fileno()
    if not os.isatty(fd):
        print("joshua-episode: error: keys reads the keyboard of a terminal; stdin is not one", file=sys.stderr)
        return EXIT_USAGE
    saved_mode = termios.tcgetattr(fd)
    try:
        with RecorderClient(node_name, domain) as client:
            if not client.found(discovery_s):
                print(no_recorder(node_name, domain, discovery_s), file=sys.stderr)
                return EXIT_NO_RECORDER
            tty.setcbreak(fd)
            print(HELP, flush=True)
            return _loop(client, fd, (EXIT_OK, EXIT_REFUSED))
    except KeyboardInterrupt:
        return EXIT_OK
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved_mode)
        print(flush=True)


def _loop(client: RecorderClient, fd: int, codes: tuple[int, int]) -> int:
    ok, refused = codes
    pending = None  # (command, answer function, deadline)
    next_redraw = 0.0
    while True:
        for key in read_keys(fd):
            if key == "quit":
                return ok
            command = KEY_COMMANDS[key]
            pending = (command, client.send(command), time.monotonic() + ANSWER_TIMEOUT_S)
        client.spin_once(0)
        if pending is not None:
            command, answer, deadline = pending
            state = answer()
            if state is not None or time.monotonic() > deadline:
                message = (state or {}).get("message") or f"no answer to {command}"
                _print_line(f"{client.node_name}: {message}")
                pending = None
                if command == "stop":  # Esc ends the session, as in lerobot-record
                    return refused if state and state["event"] == "failed" else ok
        if time.monotonic() >= next_redraw and client.progress is not None:
            next_redraw = time.monotonic() + REDRAW_PERIOD_S
            sys.stdout.write(CLEAR_LINE + describe(client.node_name, client.progress))
            sys.stdout.flush()


def _print_line(text: str) -> None:
    sys.stdout.write(CLEAR_LINE + text + "\n")
    sys.stdout.flush()
