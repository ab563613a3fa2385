"""`reload`: a newer build of the same robot applied to the running one; only what changed is restarted."""

from joshua_codegen.supervisor.build import BuildError, read_build
from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.control_request import refusal
from joshua_codegen.supervisor.node import Node
from joshua_codegen.supervisor.node_log import open_node_logs
from joshua_codegen.supervisor.policy import RESTART_DELAY_INITIAL_S
from joshua_codegen.supervisor.preflight import node_problems
from joshua_codegen.supervisor.reload_plan import build_refusal, plan_reload
from joshua_codegen.supervisor.run_mark import BUILD_SHOWN_DIGITS

RELOAD_SHOWN_PATH = 200  # characters of a build's path in a refusal


def begin_reload(plane, connection, path: str):
    """Refuse the reload of the build in `path` (one line), or apply it: its answer when no node had to be
    stopped first, else None (the Reload answers once they have)."""
    supervisor = plane.supervisor
    shown = path if path.isprintable() else repr(path)
    try:
        build = read_build(path)
        refused = build_refusal(supervisor.build, build)
        if refused:
            raise BuildError(refused)
        plan = plan_reload(supervisor.build, supervisor.nodes, build)
        starting = {
            spec["name"]: Node(spec, supervisor.options.python, build)
            for spec in build.robot["processes"]
            if spec["name"] in plan.start or spec["name"] in plan.restart
        }
        problems = [] if supervisor.options.skip_preflight else [p for n in starting.values() for p in node_problems(n)]
    except BuildError as exc:
        return refusal("invalid_build", f"cannot reload {shown:.{RELOAD_SHOWN_PATH}}: {exc}")
    except Exception as exc:  # noqa: BLE001 (data of another shape: refused before anything changed)
        return refusal(
            "invalid_build",
            f"cannot reload {shown:.{RELOAD_SHOWN_PATH}}: its data is not of this supervisor's format "
            f"({type(exc).__name__})",
        )
    if problems:
        return refusal("preflight", f"cannot reload {shown:.{RELOAD_SHOWN_PATH}}: " + "; ".join(problems))
    added = [starting[name] for name in plan.start]
    for index, node in enumerate(added):
        try:
            supervisor.containment.adopt(node)
        except OSError as exc:
            for made in added[:index]:
                supervisor.containment.release(made)
            return refusal("preflight", f"cannot reload {shown:.{RELOAD_SHOWN_PATH}}: {node.name}: {exc}")
    return Reload(plane, connection, build, plan, added).apply(shown)


class Reload:
    """One reload under way: `apply` takes the new build's processes over (restarted, started, stopped, updated,
    kept as they run) and answers `connection` once the nodes it stopped are gone and their successors started."""

    def __init__(self, plane, connection, build, plan, added):
        self.plane = plane
        self.supervisor = plane.supervisor
        self.connection = connection
        self.build = build
        self.plan = plan
        self.added = {node.name: node for node in added}
        self.previous = self.supervisor.build
        self.waiting = set()  # names of the nodes whose stop it waits for
        self.notes = []  # lines for the client beyond the lists of nodes

    def apply(self, shown: str):
        supervisor, plan = self.supervisor, self.plan
        current = {node.name: node for node in supervisor.nodes}
        supervisor.build = self.build
        supervisor.run_mark.build, supervisor.run_mark.built = self.build.digest, self.build.built
        ordered = []
        for spec in self.build.robot["processes"]:
            node = self.added.get(spec["name"]) or current[spec["name"]]
            node.rebase(spec, self.build)
            supervisor.readiness.adopt(node)
            ordered.append(node)
        removed = [current[name] for name in plan.stop]
        supervisor.nodes[:] = ordered + removed  # the same list the readiness and the tracking hold
        supervisor.readiness.all_ready = False  # the ready line is logged again once every node is
        for name, changes in list(plan.restart.items()):
            if current[name].stop_requested and not current[name].alive():  # stopped with ctl stop: it stays so
                del plan.restart[name]
                plan.update[name] = f"{changes}, applied at its next start (stopped with ctl stop)"
        grace = (self.build.sigint_grace_s, self.build.sigterm_grace_s)
        if grace != (self.previous.sigint_grace_s, self.previous.sigterm_grace_s):
            self.notes.append(f"stops now wait {grace[0]:g} s after SIGINT and {grace[1]:g} s more after SIGTERM")
        log(
            "supervisor",
            f"reload of {shown:.{RELOAD_SHOWN_PATH}}: build {short_digest(self.previous.digest)} -> "
            f"{short_digest(self.build.digest)}: {len(plan.restart)} to restart, {len(plan.start)} to start, "
            f"{len(plan.stop)} to stop, {len(plan.update)} updated, {len(plan.keep)} unchanged",
        )
        for note in self.notes:
            log("supervisor", f"reload: {note}")
        for name, changes in plan.restart.items():
            self.restart(current[name], changes)
        for node in self.added.values():
            self.start(node)
        for node in removed:
            self.remove(node)
        if self.waiting:
            self.plane.reloading = self
            return None
        return self.reply()

    def restart(self, node, changes: str) -> None:
        node.restarts, node.delay = 0, RESTART_DELAY_INITIAL_S  # a new program: its restart policy starts over
        if node.alive():
            self.waiting.add(node.name)
            self.plane.stop_node(node, f"reload: {changes} changed", then=self.restarted)
        else:
            log(node.name, f"reload: {changes} changed; it was {node.state}: starting it")
            self.plane.start(node)

    def restarted(self, node) -> None:
        if not self.supervisor.stopping:
            self.plane.start(node)
        self.done(node)

    def start(self, node) -> None:
        supervisor = self.supervisor
        for name, node_log in open_node_logs(supervisor.options.log_dir, [node.name]).items():
            node_log.begin_run(supervisor.run_mark.header())
            supervisor.logs[name] = node_log
        log(node.name, "reload: added")
        supervisor.launch(node)

    def remove(self, node) -> None:
        if node.alive():
            self.waiting.add(node.name)
            self.plane.stop_node(node, "reload: not in the new build", then=self.removed)
        else:
            self.removed(node)

    def removed(self, node) -> None:
        supervisor = self.supervisor
        if node in supervisor.nodes:
            supervisor.nodes.remove(node)
        supervisor.containment.release(node)
        supervisor.logs.pop(node.name, None)
        self.plane.since.pop(node.name, None)
        if node.pgid is not None:
            supervisor.guard.forget(node.pgid)
            node.pgid = None
        log(node.name, "reload: removed")
        self.done(node)

    def done(self, node) -> None:
        """One node the reload waited for is handled; once none is left, the client gets its answer."""
        self.waiting.discard(node.name)
        if not self.waiting and self.plane.reloading is self:
            self.plane.reloading = None
            self.connection.answer(self.reply())

    def reply(self) -> dict:
        """{"robot", "build", "previous" (stamp hashes), "restarted": [{"name", "why"}], "started", "stopped",
        "updated": [{"name", "what"}], "unchanged" (names), "notes" (lines)}."""
        plan = self.plan
        return {
            "ok": True,
            "robot": self.build.robot["name"],
            "build": self.build.digest or None,
            "previous": self.previous.digest or None,
            "restarted": [{"name": name, "why": why} for name, why in plan.restart.items()],
            "started": plan.start,
            "stopped": plan.stop,
            "updated": [{"name": name, "what": what} for name, what in plan.update.items()],
            "unchanged": plan.keep,
            "notes": self.notes,
        }


def short_digest(digest: str) -> str:
    return digest[:BUILD_SHOWN_DIGITS] or "unknown"
