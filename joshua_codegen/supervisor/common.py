"""What every part of supervisor.py uses: the log line, prctl, exit-status text, process groups, paths."""

import ctypes
import os
import signal
import sys
import time

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
START = time.monotonic()
PR_SET_PDEATHSIG, PR_SET_CHILD_SUBREAPER = 1, 36


def log(name: str, message: str) -> None:
    print(f"[{time.monotonic() - START:9.3f}] {name}: {message}", file=sys.stderr, flush=True)


def load_prctl():
    """libc's prctl, or None where ctypes cannot reach it (children then outlive a killed supervisor)."""
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    prctl.argtypes = [ctypes.c_int, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong]
    return prctl


PRCTL = load_prctl()


def signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def exit_text(status: int) -> str:
    if os.WIFSIGNALED(status):
        core = " (core dumped)" if os.WCOREDUMP(status) else ""
        return f"killed by {signal_name(os.WTERMSIG(status))}{core}"
    return f"exited with code {os.waitstatus_to_exitcode(status)}"


def group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def under_script_dir(path: str) -> str:
    return path if os.path.isabs(path) else os.path.join(SCRIPT_DIR, path)


def find_program(name: str, search_path: str) -> str | None:
    """The first executable file `name` in the directories of `search_path` (shutil.which's answer for a
    bare name, without importing shutil and the compression modules it loads: a few ms of every start)."""
    for directory in search_path.split(os.pathsep):
        candidate = os.path.join(directory or os.curdir, name)
        if executable_file(candidate):
            return candidate
    return None


def executable_file(path: str) -> bool:
    return os.access(path, os.X_OK) and os.path.isfile(path)
