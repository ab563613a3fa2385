"""The guard process: kills every descendant of the supervisor when the supervisor dies without stopping them."""

import os
import select
import signal

from joshua_codegen.supervisor.containment import (
    DescendantTracker,
    kill_cgroup,
    remove_cgroup,
)
from joshua_codegen.supervisor.policy import STOP_SIGNALS, TRACKING_POLL_S


class Guard:
    """A forked helper that, once its pipe from the supervisor reaches end-of-file (the supervisor
    exited or was killed outright), SIGKILLs what the supervisor started and may have left behind:
    - with a cgroup (`cgroup` set): every process in it, whatever session or parent it has by now
      (the kernel's cgroup.kill), then removes the cgroup;
    - without: every descendant it has seen while polling /proc every TRACKING_POLL_S (the supervisor
      is a child subreaper, so orphans stay below it), and every node's process group.
    PR_SET_PDEATHSIG alone reaches only the nodes themselves."""

    def __init__(self, cgroup: str | None):
        self.cgroup = cgroup
        self.pid: int | None = None
        self.fd: int | None = None

    def start(self) -> None:
        read_end, self.fd = os.pipe()
        supervisor = os.getpid()
        self.pid = os.fork()
        if self.pid == 0:
            # Only its pipe and the standard streams: a descriptor it kept (the control socket's listener above
            # all) would outlive the supervisor while the guard cleans up, and a supervisor started again
            # meanwhile would find the socket served.
            os.closerange(3, read_end)
            os.closerange(read_end + 1, os.sysconf("SC_OPEN_MAX"))
            self.serve(read_end, supervisor)
        os.close(read_end)

    def serve(self, read_end: int, supervisor: int) -> None:
        code = 0
        try:
            os.setsid()
            for number in STOP_SIGNALS + (signal.SIGQUIT,):
                signal.signal(number, signal.SIG_IGN)
            tracker = None if self.cgroup else DescendantTracker(supervisor, os.getpid())
            groups, pending = set(), b""
            while True:
                if tracker is not None:
                    tracker.update()
                ready, _, _ = select.select([read_end], [], [], TRACKING_POLL_S if tracker else None)
                if not ready:
                    continue
                data = os.read(read_end, 4096)
                if not data:
                    break
                pending += data
                *lines, pending = pending.split(b"\n")
                for line in lines:
                    (groups.add if line[:1] == b"+" else groups.discard)(int(line[1:]))
            if self.cgroup:
                kill_cgroup(self.cgroup)
            if tracker is not None:
                tracker.kill_all()
            for pgid in groups:
                try:
                    os.killpg(pgid, signal.SIGKILL)
                except OSError:
                    pass
            if self.cgroup and not remove_cgroup(self.cgroup):
                os.write(2, f"guard: cannot remove cgroup {self.cgroup}: processes stuck in it\n".encode())
        except BaseException:  # noqa: BLE001 (the guard ends in os._exit, never back in the supervisor's code)
            code = 1
        finally:
            os._exit(code)

    def send(self, line: str) -> None:
        if self.fd is not None:
            try:
                os.write(self.fd, line.encode())
            except OSError:
                self.fd = None

    def track(self, pgid: int) -> None:
        self.send(f"+{pgid}\n")

    def forget(self, pgid: int) -> None:
        self.send(f"-{pgid}\n")

    def stop(self) -> None:
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None
        if self.pid is not None:
            try:
                os.waitpid(self.pid, 0)
            except ChildProcessError:
                pass
            self.pid = None
