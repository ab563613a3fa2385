"""How a process that has imported heavy native libraries ends: `end_process(code)`, cheap to import.

Interpreter finalization tears down every module and runs the C++ static destructors of what was
loaded: the DDS library's alone take 0.2-0.4 s, and a process that imported torch and LeRobot spends
1.4-2.7 s on a busy 2-core machine after its last line of work. Nodes (entrypoint.py), the recorder's
dataset writer process and `joshua-train` end with `end_process` instead of returning to the
interpreter.
"""

import atexit
import os
import sys
import threading


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
