"""A forked process's command line (/proc/PID/cmdline, what ps shows) rewritten to the program it now runs."""

import ctypes
import os

STAT_ARG_START = 47  # arg_start and arg_end: fields 48 and 49 of /proc/PID/stat (proc(5)), counted from 0


def command_line_area() -> tuple[int, int]:
    """Where the kernel reads this process's command line from: (address, length)."""
    with open("/proc/self/stat", "rb") as stat:
        fields = stat.read().rsplit(b")", 1)[1].split()  # after the command name, which may hold spaces
    start, end = (int(value) for value in fields[STAT_ARG_START - 2 : STAT_ARG_START])
    return start, end - start


def set_command_line(argv: list[str]) -> None:
    """Write `argv` over this process's original arguments, cut to their length, the rest zeroed: ps then
    shows the node as it would show it exec'd. The starter is given room enough by its own arguments."""
    address, length = command_line_area()
    text = b"\0".join(os.fsencode(argument) for argument in argv)[: length - 1] + b"\0"
    ctypes.memset(address, 0, length)
    ctypes.memmove(address, text, len(text))
