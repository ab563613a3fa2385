"""In a process forked from the node starter: become the node, as an exec'd interpreter running its entrypoint."""

import os
import runpy
import signal
import sys
import time
import traceback

from joshua_runtime.node_starter.process_title import set_command_line
from joshua_runtime.process_end import die_with_parent, end_process

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
EXIT_SETUP_FAILED = 127  # the code of a program that could not be started, as the supervisor's exec failure
EXIT_ORPHANED = 125  # the supervisor ended before the node could start, as the supervisor's own child says
REPARENT_TIMEOUT_S = 5.0  # the starter's go-between exits at once; only a stopped machine takes longer
REPARENT_POLL_S = 0.0002
# A new interpreter's signal handling, which an exec'd node starts with: SIGINT raises KeyboardInterrupt,
# SIGPIPE and SIGXFSZ are ignored (their errors surface as exceptions), the rest do what the kernel does.
PYTHON_START_SIGNALS = {
    signal.SIGINT: signal.default_int_handler,
    signal.SIGPIPE: signal.SIG_IGN,
    signal.SIGXFSZ: signal.SIG_IGN,
    signal.SIGTERM: signal.SIG_DFL,
    signal.SIGHUP: signal.SIG_DFL,
    signal.SIGQUIT: signal.SIG_DFL,
    signal.SIGCHLD: signal.SIG_DFL,
}


class NodeRequest:
    """What the supervisor asked for: the request's number, the entrypoint, the node's cgroup (or None), the
    supervisor's pid and the node's environment; decoded from one request (see the package's docstring)."""

    def __init__(self, message: bytes):
        fields = message.split(b"\0")
        if len(fields) < 4 or not fields[0].isdigit() or not fields[3].isdigit():
            raise ValueError("a request has a number, an entrypoint, a cgroup and the supervisor's pid first")
        self.number = int(fields[0])
        self.entrypoint = os.fsdecode(fields[1])
        self.cgroup = os.fsdecode(fields[2]) or None
        self.supervisor = int(fields[3])
        self.environment = dict(os.fsdecode(entry).partition("=")[::2] for entry in fields[4:] if b"=" in entry)


def running(pid: int) -> bool:
    """Whether process `pid` runs (neither gone nor a zombie)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as stat:
            return stat.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except OSError:
        return False


def wait_for_supervisor(supervisor: int) -> bool:
    """Whether this process became the supervisor's child once its go-between exited."""
    deadline = time.monotonic() + REPARENT_TIMEOUT_S
    while os.getppid() != supervisor:
        if time.monotonic() > deadline:
            return False
        time.sleep(REPARENT_POLL_S)
    return True


def become_node(request: NodeRequest, python: str, output: int | None, gate: int, starter: int) -> None:
    """Set the process up as the supervisor sets up a node it execs, then run the entrypoint once `gate` (the
    read end of a pipe) is closed on its other side; never returns. Stop signals wait until the entrypoint runs.
    A node whose starter died before the gate opened ends: the supervisor, which may not have learnt its pid,
    starts the node again itself."""
    try:
        signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
        if output is not None:
            os.dup2(output, 1)
            os.dup2(output, 2)
            os.close(output)
        if request.cgroup is not None:
            with open(os.path.join(request.cgroup, "cgroup.procs"), "w") as procs:
                procs.write("0")
        while os.read(gate, 1):
            pass
        os.close(gate)
        if not running(starter):
            os._exit(EXIT_ORPHANED)
        for number, handler in PYTHON_START_SIGNALS.items():
            signal.signal(number, handler)
        os.setsid()
        if not wait_for_supervisor(request.supervisor):
            os._exit(EXIT_ORPHANED)
        die_with_parent()
        if os.getppid() != request.supervisor:  # the supervisor ended in between: no death signal will come
            os._exit(EXIT_ORPHANED)
        os.environ.clear()
        os.environ.update(request.environment)
        argv = [python, request.entrypoint]
        set_command_line(argv)
        sys.argv = argv[1:]
        sys.path[0] = os.path.dirname(request.entrypoint)
    except BaseException as exc:  # noqa: BLE001 (a forked child ends in os._exit, never back in the starter's code)
        try:
            os.write(2, f"cannot start {request.entrypoint}: {exc}\n".encode(errors="replace"))
        finally:
            os._exit(EXIT_SETUP_FAILED)
    end_process(run_entrypoint(request.entrypoint))


def run_entrypoint(path: str) -> int:
    """Run the file as the interpreter runs a script; its exit code, as the interpreter would end with it. A stop
    signal that came before it ran ends the node with 0, as the generated entrypoint ends one stopped that early."""
    started = False
    try:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
        started = True
        runpy.run_path(path, run_name="__main__")
    except SystemExit as exc:
        return exit_code(exc.code)
    except KeyboardInterrupt:  # the interpreter prints it and ends by SIGINT, so its parent sees why
        if not started:
            return 0
        traceback.print_exc()
        sys.stderr.flush()
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGINT)
        return 1
    except BaseException:  # noqa: BLE001 (an uncaught exception ends a script with its traceback and 1)
        traceback.print_exc()
        return 1
    return 0


def exit_code(code) -> int:
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    print(code, file=sys.stderr)
    return 1
