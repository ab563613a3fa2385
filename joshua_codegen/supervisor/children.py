"""The forked child of a node: own session, death signal, default signals, then exec."""

import os
import signal

from joshua_codegen.supervisor.common import PR_SET_PDEATHSIG, PRCTL
from joshua_codegen.supervisor.containment import join_cgroup
from joshua_codegen.supervisor.fd_limit import restore_fd_limit
from joshua_codegen.supervisor.policy import (
    EXIT_EXEC_FAILED,
    EXIT_ORPHANED,
    RESET_IN_CHILD,
)


def child_exec(
    argv: list[str], env: dict[str, str], parent: int, cgroup: str | None, output: int | None, held: tuple = ()
) -> None:
    """In the forked child: own session, the supervisor's cgroup, die with the supervisor, default
    signals, stdout and stderr to `output` (the node's log pipe) when given, then exec with the signals
    `held` still blocked (a Python entrypoint takes them once a stop can end it cleanly; see launching.py)."""
    try:
        if output is not None:
            os.dup2(output, 1)
            os.dup2(output, 2)
            os.close(output)
        for number in RESET_IN_CHILD:
            signal.signal(number, signal.SIG_DFL)
        signal.set_wakeup_fd(-1)
        restore_fd_limit()
        os.setsid()
        if PRCTL is not None:
            PRCTL(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if cgroup is not None:
            try:
                join_cgroup(cgroup)
            except OSError as exc:
                os.write(2, f"warning: cannot join cgroup {cgroup}: {exc}\n".encode(errors="replace"))
        if os.getppid() != parent:
            os._exit(EXIT_ORPHANED)
        signal.pthread_sigmask(signal.SIG_SETMASK, held)
        os.execve(argv[0], argv, env)
    except BaseException as exc:  # noqa: BLE001 (a forked child ends in os._exit, never back in the parent's code)
        try:
            os.write(2, f"cannot start {argv[0]}: {exc}\n".encode(errors="replace"))
        except OSError:
            pass
    finally:
        os._exit(EXIT_EXEC_FAILED)
