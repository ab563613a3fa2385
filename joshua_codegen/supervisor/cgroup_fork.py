"""Forking a child into a cgroup as the kernel makes it (clone3 with CLONE_INTO_CGROUP), instead of moving it there."""

import ctypes
import errno
import os
import signal

# Moving the first process into a cgroup (a write to cgroup.procs) waits for an RCU grace period in the kernel,
# about 10 ms that every start of the robot paid before its first node ran; a child made in its cgroup waits for none.
SYS_CLONE3 = 435  # one number on every Linux architecture: clone3 came after the syscall tables were unified
CLONE_INTO_CGROUP = 0x200000000  # Linux 5.7


class CloneArgs(ctypes.Structure):
    """struct clone_args of linux/sched.h, up to its `cgroup` field (CLONE_ARGS_SIZE_VER2)."""

    _fields_ = [
        (name, ctypes.c_uint64)
        for name in (
            "flags",
            "pidfd",
            "child_tid",
            "parent_tid",
            "exit_signal",
            "stack",
            "stack_size",
            "tls",
            "set_tid",
            "set_tid_size",
            "cgroup",
        )
    ]


def load_syscall():
    """libc's syscall(), called holding the interpreter's lock as os.fork() forks (None where ctypes cannot)."""
    try:
        call = ctypes.PyDLL(None, use_errno=True).syscall
    except (OSError, AttributeError):
        return None
    call.restype = ctypes.c_long
    call.argtypes = [ctypes.c_long, ctypes.c_void_p, ctypes.c_size_t]
    return call


SYSCALL = load_syscall()


def single_threaded() -> bool:
    try:
        return len(os.listdir("/proc/self/task")) == 1
    except OSError:
        return False


def fork_into_cgroup(path: str) -> int:
    """os.fork(), the child made in the cgroup at `path`: 0 in the child, its pid in the parent. Raises OSError, with
    no child made, where the kernel, a seccomp filter or the cgroup refuses, and in a process of several threads:
    clone3 runs none of the C library's fork handlers, so a lock another thread held would stay held in the child."""
    if SYSCALL is None:
        raise OSError(errno.ENOSYS, "no libc syscall() to call clone3 with")
    if not single_threaded():
        raise OSError(errno.ENOTSUP, "clone3 forks a single-threaded process only")
    directory = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    try:
        arguments = CloneArgs(flags=CLONE_INTO_CGROUP, exit_signal=signal.SIGCHLD, cgroup=directory)
        ctypes.pythonapi.PyOS_BeforeFork()
        pid = SYSCALL(SYS_CLONE3, ctypes.byref(arguments), ctypes.sizeof(arguments))
        if pid == 0:
            ctypes.pythonapi.PyOS_AfterFork_Child()
            return 0
        error = ctypes.get_errno()
        ctypes.pythonapi.PyOS_AfterFork_Parent()
    finally:
        os.close(directory)
    if pid < 0:
        raise OSError(error, f"clone3 into {path}: {os.strerror(error)}")
    return pid
