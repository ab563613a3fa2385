"""The stop cascade: SIGINT to every node, SIGTERM after its grace, SIGKILL after that, leftovers included."""

import os
import signal
import sys
import time

from joshua_codegen.supervisor.common import log, signal_name
from joshua_codegen.supervisor.containment import process_group
from joshua_codegen.supervisor.policy import INTERNAL_ERRORS_MAX, KILL_WAIT_S


class StopCascade:
    """The Supervisor's stopping half: uses its nodes, build (the grace periods), by_pid, guard, containment, pid,
    outcome, stage, control and internal_errors fields."""

    def request_stop(self, reason):
        if self.stopping:
            if self.stage in ("SIGINT", "SIGTERM"):
                log("supervisor", f"{reason} again: escalating now")
                self.escalate()
            return
        self.stopping = True
        log(
            "supervisor",
            f"{reason}: stopping every node (SIGINT, SIGTERM after {self.build.sigint_grace_s} s, "
            f"SIGKILL after {self.build.sigterm_grace_s} s more)",
        )
        for node in self.nodes:
            if node.state == "backoff":
                node.state = "stopped"
        if self.starter is not None:
            self.starter.stop()
        self.enter_stage("SIGINT", signal.SIGINT, self.build.sigint_grace_s)

    def enter_stage(self, stage, number, grace):
        self.stage = stage
        self.stage_deadline = time.monotonic() + grace
        now = time.monotonic()
        for node in self.nodes:
            if node.alive():
                node.state = "stopping"
                if stage == "SIGINT" and node.stop_extension_limit is None:
                    node.sigint_sent(now)
                if stage != "SIGINT":
                    self.outcome.escalated = True
                    log(node.name, f"still running: escalating to {stage}")
                self.signal_node(node, number)
        for pid in self.leftover_children():
            self.outcome.escalated = self.outcome.escalated or stage != "SIGINT"
            log("supervisor", f"sending {stage} to leftover process {pid}")
            self.signal_pid(pid, number)

    def escalate(self):
        if self.stage == "SIGINT":
            now = time.monotonic()
            held = [node.stop_extended_until for node in self.nodes if node.alive() and node.stop_held(now)]
            if held:  # a node asked for more time to stop cleanly: SIGTERM once it has run out
                self.stage_deadline = max(held)
                return
            self.enter_stage("SIGTERM", signal.SIGTERM, self.build.sigterm_grace_s)
        elif self.stage == "SIGTERM":
            self.enter_stage("SIGKILL", signal.SIGKILL, KILL_WAIT_S)
        else:
            self.stage_deadline = None
            self.gave_up = True
            for node in self.nodes:
                if node.alive():
                    log(node.name, f"still present {KILL_WAIT_S} s after SIGKILL; giving up on it")
            for pid in self.leftover_children():
                log(
                    "supervisor", f"leftover process {pid} still present {KILL_WAIT_S} s after SIGKILL; giving up on it"
                )

    def signal_node(self, node, number):
        """`number` to the node's process group and, once each, to every other process it started (in its
        cgroup, or tracked for it); SIGKILL ends all of them at once (cgroup.kill, or stopped then killed)."""
        if node.pgid is not None:
            try:
                os.killpg(node.pgid, number)
            except ProcessLookupError:
                if node.pid is not None:  # not yet in its own group (between fork and setsid)
                    self.signal_pid(node.pid, number)
        outside = [pid for pid in node.processes.pids() if process_group(pid) not in (None, node.pgid)]
        if outside:
            count = f"{len(outside)} process{'es' if len(outside) > 1 else ''}"
            log(
                node.name,
                f"{signal_name(number)} also to {count} it started outside its group: {' '.join(map(str, outside))}",
            )
        if number == signal.SIGKILL:
            node.processes.kill()
        else:
            node.processes.signal(outside, number)

    @staticmethod
    def signal_pid(pid, number):
        try:
            os.kill(pid, number)
        except ProcessLookupError:
            pass

    def leftover_children(self):
        """Children of the supervisor that belong to no node: orphans that left their group and that
        neither a cgroup nor the tracking attributes to a node."""
        known = set(self.by_pid) | {self.guard.pid} | set(self.containment.pids())
        if self.starter is not None:
            known.add(self.starter.pid)
        try:
            with open(f"/proc/{self.pid}/task/{self.pid}/children") as listing:
                children = [int(pid) for pid in listing.read().split()]
        except OSError:
            children = []
        return [pid for pid in children if pid not in known]

    def on_internal_error(self):
        """An exception the supervisor did not expect: log its traceback, stop serving the control socket,
        and stop every node with the cascade; after INTERNAL_ERRORS_MAX of them, SIGKILL what is left."""
        import traceback

        self.internal_errors += 1
        self.outcome.internal_error = True
        log("supervisor", f"internal error {self.internal_errors} (a bug in supervisor.py); its traceback:")
        sys.stderr.write(traceback.format_exc())
        sys.stderr.flush()
        if self.internal_errors >= INTERNAL_ERRORS_MAX:
            log("supervisor", f"{self.internal_errors} internal errors: killing every process left (SIGKILL)")
            self.gave_up = True  # the loop ends; the guard kills whatever the SIGKILL below misses
            try:
                self.enter_stage("SIGKILL", signal.SIGKILL, KILL_WAIT_S)
            except Exception:  # noqa: BLE001 (the guard still kills every descendant once the loop ends)
                pass
            return
        control, self.control = self.control, None
        if control is not None:
            try:
                control.close()
            except Exception:  # noqa: BLE001 (already stopping for a bug; the socket file may stay behind)
                pass
        if not self.stopping:
            self.request_stop("internal error (a bug in supervisor.py)")
