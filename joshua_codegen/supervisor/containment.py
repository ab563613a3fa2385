"""Keeping every descendant of the supervisor killable: a cgroup where writable, else /proc tracking."""

import os
import select
import signal
import time

from joshua_codegen.supervisor.cgroup_fork import fork_into_cgroup
from joshua_codegen.supervisor.policy import (
    CGROUP_EMPTY_POLL_S,
    KILL_WAIT_S,
    STOP_SETTLE_S,
)

CGROUP2_MOUNTS = "/proc/self/mountinfo"
OWN_CGROUP = "/proc/self/cgroup"


def cgroup2_mount() -> str | None:
    """Where the unified (v2) cgroup hierarchy is mounted, or None."""
    try:
        with open(CGROUP2_MOUNTS) as mounts:
            for line in mounts:
                fields = line.split()
                separator = fields.index("-")
                if fields[separator + 1] == "cgroup2":
                    return fields[4]
    except (OSError, ValueError, IndexError):
        return None
    return None


def own_cgroup() -> str | None:
    """This process's cgroup in the unified hierarchy (the `0::` line), or None."""
    try:
        with open(OWN_CGROUP) as lines:
            for line in lines:
                if line.startswith("0::"):
                    return line[3:].strip()
    except OSError:
        return None
    return None


def create_cgroup(name: str) -> str:
    """A new, empty cgroup `name` below this process's own one; raises OSError where that is not possible.

    No existing process is moved: only the nodes' children join it (each the cgroup of its node below
    it), each on its own before exec.
    """
    mount, own = cgroup2_mount(), own_cgroup()
    if mount is None or own is None:
        raise OSError("no unified (v2) cgroup hierarchy is mounted")
    path = os.path.join(mount, own.lstrip("/"), name)
    os.mkdir(path)
    if not os.path.exists(os.path.join(path, "cgroup.kill")):
        remove_cgroup(path)
        raise OSError("the kernel has no cgroup.kill (Linux 5.14 or later)")
    return path


def join_cgroup(path: str) -> None:
    """Move the calling process (a freshly forked child) into the cgroup at `path`."""
    with open(os.path.join(path, "cgroup.procs"), "w") as procs:
        procs.write(str(os.getpid()))


def cgroup_usable(path: str, made_in: bool) -> bool:
    """Whether a child can be forked in the cgroup (clone3, `made_in`), else join it after its fork, and live: tried
    once by a short-lived child. The kernel kills a child forked in where this process's cgroup was ever killed
    through cgroup.kill (and the new one not)."""
    try:
        pid = fork_into_cgroup(path) if made_in else os.fork()
    except OSError:
        return False
    if pid == 0:
        code = 1
        try:
            if not made_in:
                join_cgroup(path)
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status) == 0


def cgroup_populated(path: str) -> bool:
    try:
        with open(os.path.join(path, "cgroup.events")) as events:
            return "populated 1" in events.read()
    except OSError:
        return False


def kill_cgroup(path: str) -> None:
    """SIGKILL every process in the cgroup (the kernel does it at once, forks in flight included)."""
    try:
        with open(os.path.join(path, "cgroup.kill"), "w") as kill:
            kill.write("1")
    except OSError:
        pass


def cgroup_pids(path: str) -> list[int]:
    """The processes in the cgroup at `path` and in the cgroups below it; none when it is gone."""
    found = []
    for directory, _, _ in os.walk(path):
        try:
            with open(os.path.join(directory, "cgroup.procs")) as procs:
                found.extend(int(pid) for pid in procs.read().split())
        except OSError:
            continue
    return found


def remove_cgroup(path: str) -> bool:
    """Remove the cgroup and the cgroups below it once their processes are gone (waiting up to
    KILL_WAIT_S); whether it is gone."""
    deadline = time.monotonic() + KILL_WAIT_S
    while cgroup_populated(path) and time.monotonic() < deadline:
        time.sleep(CGROUP_EMPTY_POLL_S)
    try:
        below = [entry.path for entry in os.scandir(path) if entry.is_dir(follow_symlinks=False)]
    except FileNotFoundError:
        return True
    except OSError:
        below = []
    for child in below:
        remove_cgroup(child)
    try:
        os.rmdir(path)
    except FileNotFoundError:
        return True
    except OSError:
        return False
    return True


def children_of(pid: int) -> list[int]:
    """The children of every thread of process `pid` (none when it is gone)."""
    try:
        threads = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return []
    found = []
    for thread in threads:
        try:
            with open(f"/proc/{pid}/task/{thread}/children") as listing:
                found.extend(int(child) for child in listing.read().split())
        except OSError:
            continue
    return found


def open_pidfd(pid: int) -> int | None:
    """A pidfd for `pid` (so a later signal cannot reach a reused PID), None if it is gone or unsupported."""
    try:
        return os.pidfd_open(pid)
    except (OSError, AttributeError):
        return None


def send_signal(pidfd: int, number: int) -> None:
    try:
        signal.pidfd_send_signal(pidfd, number)
    except (OSError, AttributeError):
        pass


def exited(pidfds: list[int]) -> set[int]:
    """Those of `pidfds` whose process has ended (a pidfd is readable from then on; a zombie has ended)."""
    poller = select.poll()
    for pidfd in pidfds:
        poller.register(pidfd, select.POLLIN)
    return {pidfd for pidfd, _ in poller.poll(0)}


def process_group(pid: int) -> int | None:
    """The process group of `pid`, None when it is gone or a zombie."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            fields = stat.read().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return None
    return None if fields[0] == "Z" else int(fields[2])


class TrackedProcesses:
    """Processes held by pidfd (so a signal never reaches a reused PID), killed as one with kill_all."""

    def __init__(self, exclude: tuple[int, ...] = ()):
        self.exclude = set(exclude)  # never tracked (the tracker's own process, the supervisor)
        self.known: dict[int, int] = {}  # pid -> pidfd

    def add(self, pid: int) -> bool:
        if pid in self.known or pid in self.exclude:
            return False
        pidfd = open_pidfd(pid)
        if pidfd is None:
            return False
        self.known[pid] = pidfd
        return True

    def forget(self, pid: int) -> None:
        os.close(self.known.pop(pid))

    def forget_exited(self) -> None:
        ended = exited(list(self.known.values()))
        for pid in [pid for pid, pidfd in self.known.items() if pidfd in ended]:
            self.forget(pid)

    def kill_all(self) -> list[int]:
        """Stop every known process (a stopped process cannot fork), add their children until a pass
        finds none new (once more after STOP_SETTLE_S, for forks that were in flight), then SIGKILL all;
        the PIDs killed."""
        stopped: set[int] = set()
        settled = False
        while True:
            for pid in [pid for pid in self.known if pid not in stopped]:
                send_signal(self.known[pid], signal.SIGSTOP)
                stopped.add(pid)
            if not [child for pid in list(self.known) for child in children_of(pid) if self.add(child)]:
                if settled:
                    break
                settled = True
                time.sleep(STOP_SETTLE_S)
        killed = list(self.known)
        for pid in killed:
            send_signal(self.known[pid], signal.SIGKILL)
            self.forget(pid)
        return killed


def descendants_of(root: int, exclude: set[int]) -> list[int]:
    """Every process below `root` in the process tree now, except `exclude` and what is below those."""
    found, frontier, seen = [], [root], {root, *exclude}
    while frontier:
        for child in children_of(frontier.pop()):
            if child not in seen:
                seen.add(child)
                found.append(child)
                frontier.append(child)
    return found


class DescendantTracker(TrackedProcesses):
    """Every descendant of a root process, found by walking /proc's children lists; since the root is a
    child subreaper, processes orphaned anywhere below it are reparented to it and stay found."""

    def __init__(self, root: int, exclude: int):
        super().__init__((root, exclude))  # exclude: the tracker's own process (a child of the root)
        self.root = root

    def update(self) -> None:
        """One poll while the root lives: find new descendants, forget the ones that are gone."""
        current = set(descendants_of(self.root, self.exclude))
        for pid in list(self.known):
            if pid not in current:
                self.forget(pid)
        for pid in current:
            self.add(pid)
