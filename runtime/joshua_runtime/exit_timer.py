"""`exit_after(seconds, code)`: ends the process from a C library thread if a block has not finished in time.

Python cannot time out a native call that blocks while it holds the GIL: no other Python thread runs
again, and signal handlers wait for the main thread. Fast DDS 2.14 has such a call: when a process
deletes its DDS participant while a remote participant's leaving is reported to it, `set_listener`
waits forever for that report, which waits for a lock the waiting thread holds. A robot's nodes all
stop at once, so this happens in about one stop of a node in a thousand, and the node then waits for
the supervisor's SIGKILL.

A POSIX timer with SIGEV_THREAD makes glibc start a thread of its own when the timer expires and call
`_exit(code)` on it, without Python: the process ends with the code it would have ended with, its
streams flushed before the block (the block's own prints are not).
"""

import contextlib
import ctypes
import sys

CLOCK_MONOTONIC = 1
SIGEV_THREAD = 2
NANOSECONDS = 1_000_000_000


class _SigEvent(ctypes.Structure):
    """glibc's struct sigevent on Linux x86_64 (64 bytes), with its SIGEV_THREAD members."""

    _fields_ = [
        ("value", ctypes.c_void_p),  # union sigval: passed to the function in the register of an int argument
        ("signo", ctypes.c_int),
        ("notify", ctypes.c_int),
        ("function", ctypes.c_void_p),
        ("attributes", ctypes.c_void_p),
        ("padding", ctypes.c_int * 8),
    ]


class _TimeSpec(ctypes.Structure):
    _fields_ = [("seconds", ctypes.c_long), ("nanoseconds", ctypes.c_long)]


class _TimerSpec(ctypes.Structure):
    _fields_ = [("interval", _TimeSpec), ("value", _TimeSpec)]


def _libc():
    libc = ctypes.CDLL(None, use_errno=True)
    libc.timer_create.argtypes = [ctypes.c_int, ctypes.POINTER(_SigEvent), ctypes.POINTER(ctypes.c_void_p)]
    libc.timer_settime.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(_TimerSpec), ctypes.c_void_p]
    libc.timer_delete.argtypes = [ctypes.c_void_p]
    return libc


@contextlib.contextmanager
def exit_after(seconds: float, code: int):
    """Run the block; if it has not finished `seconds` after it began, the process ends with exit code `code`.

    Without the timer (the C library refuses one) the block runs without a deadline.
    """
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError, AttributeError):
            stream.flush()
    libc = _libc()
    event = _SigEvent(value=code & 0xFF, notify=SIGEV_THREAD, function=ctypes.cast(libc._exit, ctypes.c_void_p).value)
    timer = ctypes.c_void_p()
    if libc.timer_create(CLOCK_MONOTONIC, ctypes.byref(event), ctypes.byref(timer)) != 0:
        yield
        return
    whole = int(seconds)
    expiry = _TimerSpec(value=_TimeSpec(whole, int((seconds - whole) * NANOSECONDS)))
    try:
        libc.timer_settime(timer, 0, ctypes.byref(expiry), None)
        yield
    finally:
        libc.timer_delete(timer)
