"""How a process that has imported heavy native libraries ends: `end_process(code)`, cheap to import.

Interpreter finalization tears down every module and runs the C++ static destructors of what was
loaded: the DDS library's alone take 0.2-0.4 s, and a process that imported torch and LeRobot spends
1.4-2.7 s on a busy 2-core machine after its last line of work. Nodes (entrypoint.py), the dashboard
(its generated entrypoint), the recorder's dataset writer process and `joshua-train` end with
`end_process` instead of returning to the interpreter. `die_with_parent()` makes a process end with
the one that started it.
"""

import atexit
import ctypes
import os
import signal
import sys
import threading

PR_SET_PDEATHSIG = 1


def end_process(code: int) -> None:
    """Exit like a normal interpreter exit, minus the slow native teardown.

    Non-daemon threads are joined and atexit handlers run, as `sys.exit` would do; then stdio is
    flushed and the process ends with os._exit, skipping interpreter finalization and the C++
    static destructors of the native libraries.
    """
    current = threading.current_thread()
    for thread in threading.enumerate():
        if thread is not current and not thread.daemon:
            thread.join()
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def die_with_parent() -> None:
    """Ask the kernel to SIGKILL this process when its parent dies (nothing where prctl cannot be called)."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        pass
