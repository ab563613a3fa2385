"""What each node started, kept apart per node: in the node's own cgroup, else tracked through /proc."""

import os

from joshua_codegen.supervisor.cgroup_fork import fork_into_cgroup
from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.containment import (
    TrackedProcesses,
    cgroup_pids,
    cgroup_populated,
    cgroup_usable,
    children_of,
    create_cgroup,
    descendants_of,
    kill_cgroup,
    remove_cgroup,
    send_signal,
)
from joshua_codegen.supervisor.policy import TRACKING_POLL_S
from joshua_codegen.supervisor.robot import ROBOT

# Every node's environment holds "<supervisor pid>:<node name>" in NODE_MARK_VARIABLE: without a cgroup,
# a process orphaned before the supervisor saw it is recognised by it.
NODE_MARK_VARIABLE = "JOSHUA_SUPERVISOR_NODE"

ENDED_STATES = ("failed", "finished")  # a node in one of these does not run again unless asked to


def node_mark(supervisor: int, name: str) -> str:
    return f"{supervisor}:{name}"


def environment_mark(pid: int) -> str | None:
    """The NODE_MARK_VARIABLE value `pid` was started with, None when it has none or cannot be read."""
    prefix = f"{NODE_MARK_VARIABLE}=".encode()
    try:
        with open(f"/proc/{pid}/environ", "rb") as environ:
            entries = environ.read().split(b"\0")
    except OSError:
        return None
    return next((entry[len(prefix) :].decode(errors="replace") for entry in entries if entry.startswith(prefix)), None)


class NodeCgroup:
    """A node's own cgroup: every process it started stays in it, whatever session, group or parent it
    moves to (only a write to the cgroup tree moves a process out)."""

    def __init__(self, path: str, made_in: bool):
        self.path = path
        self.made_in = made_in  # whether its process is forked in the cgroup, else it joins it before exec

    @property
    def join(self) -> str | None:
        """The cgroup a forked process of the node joins before exec (None: it is forked in it)."""
        return None if self.made_in else self.path

    def fork(self) -> int:
        if self.made_in:
            try:
                return fork_into_cgroup(self.path)
            except OSError:  # refused now (out of processes, say): this fork and the next the other way
                self.made_in = False
        return os.fork()

    def pids(self) -> list[int]:
        return cgroup_pids(self.path)

    def alive(self) -> bool:
        return cgroup_populated(self.path)

    def signal(self, pids: list[int], number: int) -> None:
        for pid in pids:
            try:
                os.kill(pid, number)
            except ProcessLookupError:
                pass

    def kill(self) -> None:
        kill_cgroup(self.path)
        # The kernel kills a child forked into a cgroup whose count of kills differs from its parent's cgroup's
        # (Linux 6.18 at least): after a kill, the node's processes join its cgroup after their fork.
        self.made_in = False


class CgroupContainment:
    """A new cgroup of the supervisor's, holding one cgroup per node and no process of its own."""

    def __init__(self, path: str, nodes, made_in: bool):
        self.cgroup = path  # the guard kills and removes it with everything below
        self.made_in = made_in  # whether nodes are forked in their cgroups (clone3), else moved there
        for node in nodes:
            node.processes = NodeCgroup(os.path.join(path, node.name), made_in)

    def adopt(self, node) -> None:
        """Give a node a reload adds its own cgroup; raises OSError when it cannot be made."""
        path = os.path.join(self.cgroup, node.name)
        try:
            os.mkdir(path)
        except FileExistsError:
            pass
        node.processes = NodeCgroup(path, self.made_in)

    def release(self, node) -> None:
        """Remove the cgroup of a node a reload took away, once it is empty."""
        remove_cgroup(node.processes.path)

    def pids(self) -> list[int]:
        """The processes of every node."""
        return cgroup_pids(self.cgroup)

    def before_sleep(self):
        return None

    def node_exited(self) -> None:
        pass

    def poll(self, now: float) -> None:
        pass

    def close(self) -> None:
        """At the supervisor's exit, after its guard's: what the guard does, in case the guard is gone."""
        kill_cgroup(self.cgroup)
        remove_cgroup(self.cgroup)


class NodeDescendants(TrackedProcesses):
    """Without a cgroup: the processes of one node, as its NodeTracker found them (refreshed on each use)."""

    def __init__(self, tracker):
        super().__init__()
        self.tracker = tracker
        self.join = None

    def fork(self) -> int:
        return os.fork()

    def pids(self) -> list[int]:
        self.tracker.update()
        return list(self.known)

    def alive(self) -> bool:
        self.tracker.refresh()
        self.forget_exited()
        return bool(self.known)

    def signal(self, pids: list[int], number: int) -> None:
        for pid in pids:
            if pid in self.known:
                send_signal(self.known[pid], number)

    def kill(self) -> None:
        self.tracker.update()
        self.kill_all()

    def kill_all(self) -> list[int]:
        killed = super().kill_all()
        self.tracker.strangers.update(killed)  # dying, maybe not gone by the next walk: not a leftover found then
        return killed


class NodeTracker:
    """Without a cgroup: every descendant of the supervisor, attributed to the node that started it.

    A process below a node's running process is that node's. The supervisor is a child subreaper, so a
    process whose parent died becomes its child: it stays with the node it was seen with, else it is the
    node's its environment names (NODE_MARK_VARIABLE); a process that is neither belongs to no node. Known
    processes are held by pidfd and looked for again every TRACKING_POLL_S while any node may run."""

    cgroup = None

    def __init__(self, supervisor: int, nodes):
        self.supervisor = supervisor
        self.nodes = nodes
        self.strangers: set[int] = set()  # children of the supervisor that belong to no node
        self.next_poll = 0.0
        self.stale = True  # processes may have come or gone since the last update (see before_sleep)
        for node in nodes:
            node.processes = NodeDescendants(self)

    def adopt(self, node) -> None:
        """Track a node a reload adds (it is in `nodes`, the supervisor's list, from then on)."""
        node.processes = NodeDescendants(self)

    def release(self, node) -> None:
        """Forget a node a reload took away."""
        for pid in list(node.processes.known):
            node.processes.forget(pid)

    def owner(self, pid: int):
        """The NodeDescendants an orphan `pid` belongs to, or None."""
        for node in self.nodes:
            if pid in node.processes.known:
                return node.processes
        mark = environment_mark(pid)
        return next((n.processes for n in self.nodes if mark == node_mark(self.supervisor, n.name)), None)

    def refresh(self) -> None:
        if self.stale:
            self.update()

    def update(self) -> None:
        """Walk /proc from every node's running process and every orphan belonging to a node."""
        self.stale = False
        roots = {node.pid: node.processes for node in self.nodes if node.pid is not None}
        children = children_of(self.supervisor)
        self.strangers &= set(children)
        for child in children:
            if child not in roots and child not in self.strangers:
                owner = self.owner(child)
                if owner is None:
                    self.strangers.add(child)
                else:
                    roots[child] = owner
        for root, owner in roots.items():
            for pid in [root, *descendants_of(root, {self.supervisor})]:
                owner.add(pid)
        for node in self.nodes:
            node.processes.forget_exited()

    def pids(self) -> list[int]:
        """The processes of every node."""
        self.update()
        return [pid for node in self.nodes for pid in node.processes.known]

    def busy(self) -> bool:
        return any(node.pid is not None or node.processes.known for node in self.nodes)

    def before_sleep(self):
        """Told by the supervisor's loop as it goes to sleep: the first question about a node after it
        walks /proc again (the ones after that, in the same instant, do not). The moment the next poll is
        due, None while no node has a process."""
        self.stale = True
        return self.next_poll if self.busy() else None

    def node_exited(self) -> None:
        """A node's process exited: the next question about its processes walks /proc again, also in the
        instant of the last walk (what the node started just before its exit was not there yet)."""
        self.stale = True

    def poll(self, now: float) -> None:
        if now >= self.next_poll and self.busy():
            self.update()
            self.next_poll = now + TRACKING_POLL_S
            self.kill_late_leftovers()

    def kill_late_leftovers(self) -> None:
        """Kill what a node that will not run again left behind and the walk found only after its exit: a process
        on its way to the supervisor as the node exited (its own parent exiting at that moment too). A node that
        restarts has its leftovers killed before the restart; a cgroup never misses one."""
        for node in self.nodes:
            if node.state in ENDED_STATES and node.processes.known:
                log(node.name, "killing what it left behind, found after its exit")
                node.processes.kill_all()

    def close(self) -> None:
        for node in self.nodes:
            for pid in list(node.processes.known):
                node.processes.forget(pid)


def contain_nodes(nodes, supervisor: int, no_cgroup: bool):
    """A CgroupContainment in a new cgroup `joshua-<robot>-<pid>` where one can be made (so that the
    guard and each node's stop can kill what the nodes leave behind), else a NodeTracker."""
    reason = "--no-cgroup"
    if not no_cgroup:
        try:
            path = create_cgroup(f"joshua-{ROBOT['name']}-{supervisor}")
        except OSError as exc:
            reason = str(exc)
        else:
            try:
                for node in nodes:
                    os.mkdir(os.path.join(path, node.name))
            except OSError as exc:
                reason = f"cannot create a cgroup per node in {path}: {exc}"
            else:
                probe = os.path.join(path, nodes[0].name) if nodes else path
                made_in = cgroup_usable(probe, made_in=True)
                if made_in or cgroup_usable(probe, made_in=False):
                    log("supervisor", f"nodes run in cgroup {path}")
                    if not made_in:
                        log("supervisor", "each node joins its cgroup after its fork (clone3 cannot fork it there)")
                    return CgroupContainment(path, nodes, made_in)
                reason = f"a process cannot join {probe}"
            remove_cgroup(path)
    log(
        "supervisor",
        f"no cgroup for the nodes ({reason}); the guard tracks their descendants through /proc every "
        f"{TRACKING_POLL_S} s, and the supervisor which node started each",
    )
    return NodeTracker(supervisor, nodes)
