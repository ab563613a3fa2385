"""The event loop: launching, reaping and restarts with backoff."""

import os
import signal
import time

from joshua_codegen.supervisor.build import running_build
from joshua_codegen.supervisor.common import (
    PR_SET_CHILD_SUBREAPER,
    PRCTL,
    START,
    exit_text,
    group_alive,
    log,
    signal_name,
)
from joshua_codegen.supervisor.control import ControlPlane, control_clients_max
from joshua_codegen.supervisor.control_socket import ControlSocketError
from joshua_codegen.supervisor.fd_limit import raise_fd_limit
from joshua_codegen.supervisor.guard import Guard
from joshua_codegen.supervisor.launching import Launching
from joshua_codegen.supervisor.node import Node
from joshua_codegen.supervisor.node_log import open_node_logs
from joshua_codegen.supervisor.node_processes import contain_nodes
from joshua_codegen.supervisor.notify import Readiness
from joshua_codegen.supervisor.outcome import Outcome
from joshua_codegen.supervisor.policy import (
    EXIT_PREFLIGHT,
    FIRST_READY_TIMEOUT_S,
    LEFTOVER_POLL_S,
    RESTART_DELAY_CAP_S,
    RESTART_DELAY_FACTOR,
    RESTART_DELAY_INITIAL_S,
    RESTART_RESET_AFTER_S,
    SHM_CLOCK_SLACK_S,
    SHM_RECHECKS_S,
    STOP_SIGNALS,
)
from joshua_codegen.supervisor.poller import Poller
from joshua_codegen.supervisor.robot import ROBOT
from joshua_codegen.supervisor.run_mark import RunMark
from joshua_codegen.supervisor.shm import remove_abandoned_segments
from joshua_codegen.supervisor.stop_cascade import StopCascade


class Supervisor(StopCascade, Launching):
    def __init__(self, options):
        self.options = options
        self.run_mark = RunMark()
        log("supervisor", self.run_mark.header())
        self.build = running_build()  # where the nodes' files are and what they run: a reload replaces it
        self.nodes = [Node(spec, options.python, self.build) for spec in ROBOT["processes"]]
        self.by_pid = {}
        self.guard = Guard(None)
        self.containment = None  # where each node's processes are kept apart (see node_processes.py), from run()
        self.starter = None  # the NodeStarter that forks the Python nodes, where one is used (from run())
        self.pid = os.getpid()
        self.wakeup = None
        self.poller = Poller()
        self.readers = self.poller.readers  # fd -> callable run when the fd is readable
        self.writers = self.poller.writers  # fd -> callable run when the fd is writable
        self.internal_errors = 0  # exceptions the supervisor did not expect (bugs), see on_internal_error
        self.abandoned_since = None  # while reaping: launch time of the first node that ended abnormally
        self.shm_recheck = None  # (when, since, looks done): abandoned segments are looked for again then
        self.requests = []  # stop signals received, handled by the main loop
        self.stopping = False
        self.stage = ""  # "", "SIGINT", "SIGTERM", "SIGKILL"
        self.stage_deadline = None
        self.gave_up = False  # processes survived SIGKILL for KILL_WAIT_S (stuck in the kernel): exit anyway
        self.outcome = Outcome()
        self.duration_end = START + options.duration if options.duration else None
        self.next_status = START + options.status_interval if options.status_interval else None
        self.readiness = Readiness(self.nodes, ROBOT["name"])
        self.control = None  # the ControlPlane while the control socket is served
        self.logs = open_node_logs(options.log_dir, [node.name for node in self.nodes])  # empty: output not kept
        self.first = [node for node in self.nodes if node.spec.get("starts_first")]  # the others wait for them
        self.held_until = None  # while the others wait: when they start even if the first are not ready

    # Setup

    def install_signals(self):
        read_end, write_end = os.pipe()
        os.set_blocking(read_end, False)
        os.set_blocking(write_end, False)
        self.wakeup = read_end
        self.readers[read_end] = self.drain_wakeup
        signal.set_wakeup_fd(write_end, warn_on_full_buffer=False)
        signal.signal(signal.SIGCHLD, lambda number, frame: None)
        self.take_stop_signals()
        if self.requests:  # one came before the wakeup descriptor: the loop's first wait must not sleep on it
            os.write(write_end, b"\0")

    def take_stop_signals(self):
        """From now on a stop signal is a stop request, taken by the loop (before it runs, by supervise())."""
        for number in STOP_SIGNALS:
            if number == signal.SIGHUP and signal.getsignal(number) == signal.SIG_IGN:
                continue  # started under nohup: keep ignoring hangups
            signal.signal(number, lambda number, frame: self.requests.append(number))

    def run(self):
        fd_limit = raise_fd_limit()
        if self.options.control_socket:
            try:
                self.control = ControlPlane(
                    self, self.options.control_socket, control_clients_max(fd_limit, len(self.nodes))
                )
            except ControlSocketError as exc:
                log("supervisor", f"cannot serve the control socket {self.options.control_socket}: {exc}")
                return EXIT_PREFLIGHT
        for node_log in self.logs.values():  # here, as the nodes start: a run refused before leaves no header
            node_log.begin_run(self.run_mark.header())
        try:
            self.start()
        except Exception:  # noqa: BLE001 (a bug: logged, and every node started so far is stopped)
            self.on_internal_error()
        while True:
            try:
                if self.finished():
                    break
                self.turn()
            except Exception:  # noqa: BLE001 (a bug: logged, and the robot is stopped)
                self.on_internal_error()
        return self.shut_down()

    def start(self):
        if PRCTL is not None:
            PRCTL(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
        else:
            log("supervisor", "warning: prctl is unavailable; nodes will outlive a killed supervisor")
        self.containment = contain_nodes(self.nodes, self.pid, self.options.no_cgroup)
        self.starter = self.node_starter()
        self.guard = Guard(self.containment.cgroup)
        self.guard.start()
        self.install_signals()
        self.readers[self.readiness.fileno()] = lambda: self.readiness.receive(self.by_pid.get, time.monotonic())
        log("supervisor", f"robot {ROBOT['name']}: starting {len(self.nodes)} nodes")
        if self.first:
            names = ", ".join(node.name for node in self.first)
            log("supervisor", f"starting {names} first; the others once it is ready")
            self.held_until = time.monotonic() + FIRST_READY_TIMEOUT_S
        self.launch_all(self.first or self.nodes)  # asked to stop while starting: the rest stay pending
        running = sum(node.state == "running" for node in self.nodes)
        log(
            "supervisor",
            f"started: {running} of {len(self.nodes)} nodes running "
            f"({(time.monotonic() - START) * 1000:.1f} ms after start); waiting for them to be ready",
        )
        if not self.requests:
            self.readiness.check_all(time.monotonic())  # CUSTOM programs are ready at once: the loop may sleep long

    def start_held(self, now):
        """Start the nodes that wait for the first ones, once those are ready (or waited for long enough)."""
        if self.held_until is None or self.stopping:
            return
        if not all(node.ready for node in self.first) and now < self.held_until:
            return
        if now >= self.held_until and not all(node.ready for node in self.first):
            log("supervisor", f"warning: not ready after {FIRST_READY_TIMEOUT_S:g} s: starting the other nodes anyway")
        self.held_until = None
        self.launch_all([node for node in self.nodes if node.state == "pending" and not node.stop_requested])

    def turn(self):
        """One turn of the loop: wait, reap, take stop requests, run what is due. After an internal error
        only the stop cascade runs, so a fault elsewhere cannot come back."""
        if self.outcome.internal_error:  # until the cascade's next step; what else is due waits for good
            due = LEFTOVER_POLL_S if self.stage_deadline is None else self.stage_deadline - time.monotonic()
            if self.containment is not None:
                self.containment.before_sleep()  # the nodes' processes are looked for anew after the sleep
            self.wait(max(0.0, min(due, LEFTOVER_POLL_S)))
        else:
            self.wait(self.timeout())
        self.reap()
        while self.requests:
            self.request_stop(f"received {signal_name(self.requests.pop(0))}")
        if self.outcome.internal_error:
            if self.stage_deadline is not None and time.monotonic() >= self.stage_deadline:
                self.escalate()
        else:
            self.on_timers()

    def shut_down(self):
        if self.starter is not None:
            self.starter.close()
        self.guard.stop()
        if self.containment is not None:
            self.containment.close()
        if self.control is not None:
            self.control.close()
        for node in self.nodes:
            log(node.name, f"final state: {node.status_line(time.monotonic())}")
        for line in self.outcome.last_lines():
            log("supervisor", line)
        return self.outcome.exit_code()

    # Launching and reaping

    def reap(self):
        self.abandoned_since = None
        while True:
            try:
                pid, status = os.waitpid(-1, os.WNOHANG)
            except ChildProcessError:
                break
            if pid == 0:
                break
            node = self.by_pid.pop(pid, None)
            if self.starter is not None and pid == self.starter.pid:
                self.starter.exited(status)
                self.guard.forget(pid)
            elif pid == self.guard.pid:
                self.guard.pid = None
                log(
                    "supervisor",
                    f"warning: guard process {pid} {exit_text(status)}; nodes will outlive a killed supervisor",
                )
            elif node is None:
                log("supervisor", f"reaped leftover process {pid} ({exit_text(status)})")
            else:
                self.on_exit(node, pid, status)
        if self.abandoned_since is not None:
            since = self.abandoned_since - SHM_CLOCK_SLACK_S
            self.remove_abandoned_shm(since)
            if self.shm_recheck is not None:
                since = min(since, self.shm_recheck[1])
            self.shm_recheck = (time.monotonic() + SHM_RECHECKS_S[0], since, 0)
        for node in self.nodes:
            if node.pid is None and node.pgid is not None and not group_alive(node.pgid):
                self.guard.forget(node.pgid)
                node.pgid = None
            if node.state == "stopping" and not node.alive():
                node.state = "stopped"

    def remove_abandoned_shm(self, since):
        files, size = remove_abandoned_segments(since)
        if files:
            log(
                "supervisor",
                f"removed {files} Fast DDS shared-memory files ({size / 2**20:.1f} MiB) "
                "that dead processes left in /dev/shm",
            )

    def on_exit(self, node, pid, status):
        node.pid = None
        self.readiness.on_exit(node)
        node.last_exit = exit_text(status)
        ran_for = time.monotonic() - node.started_at
        log(node.name, f"pid {pid} {node.last_exit} after {ran_for:.3f} s")
        code = os.waitstatus_to_exitcode(status) if os.WIFEXITED(status) else None
        self.outcome.on_node_exit(node.spec, code)
        if code != 0:  # it may not have removed its shared-memory segments
            self.abandoned_since = min(node.started_at_wall, self.abandoned_since or node.started_at_wall)
        self.containment.node_exited()
        if self.stopping or node.stop_requested:
            node.state = "stopping" if node.alive() else "stopped"
            return
        if node.alive():
            log(node.name, "killing what it left behind")
            self.signal_node(node, signal.SIGKILL)
        if code == ROBOT["node_exit_codes"]["settings"] and node.spec["kind"] != "custom":
            self.give_up(node, f"exited with code {code}: its settings are unusable and a restart cannot fix them")
            return
        self.after_exit(node, code != 0, ran_for)

    def after_exit(self, node, failed, ran_for):
        spec = node.spec
        if ran_for >= RESTART_RESET_AFTER_S:
            node.restarts, node.delay = 0, RESTART_DELAY_INITIAL_S
        wanted = spec["restart"] == "RESTART_ALWAYS" or (spec["restart"] == "RESTART_ON_FAILURE" and failed)
        if not wanted:
            if failed:
                self.give_up(node, f"failed ({spec['restart']})")
            else:
                node.state = "finished"
                log(node.name, "finished")
            return
        if node.restarts >= spec["max_restarts"]:
            self.give_up(node, f"failed for good after {node.restarts} restarts (max_restarts {spec['max_restarts']})")
            return
        node.restarts += 1
        node.state = "backoff"
        node.restart_at = time.monotonic() + node.delay
        log(node.name, f"restarting in {node.delay:.2f} s (restart {node.restarts} of {spec['max_restarts']})")
        node.delay = min(node.delay * RESTART_DELAY_FACTOR, RESTART_DELAY_CAP_S)

    def give_up(self, node, reason):
        node.state = "failed"
        if node.spec["critical"]:
            self.outcome.critical_failure = True
            log(node.name, f"{reason}; critical node: stopping the robot")
            self.request_stop(f"critical node {node.name} failed")
        else:
            self.outcome.node_failure = True
            log(node.name, f"{reason}; not critical: the other nodes keep running")

    # The loop

    def finished(self):
        if self.gave_up:
            return True
        if not self.stopping and any(node.state in ("running", "backoff", "pending") for node in self.nodes):
            return False
        if not self.stopping and any(node.stop_requested for node in self.nodes):
            return False  # stopped over the control socket: it may be started again
        if not any(node.alive() for node in self.nodes) and not self.leftover_children():
            return True
        if not self.stopping:
            self.request_stop("every node has finished")
        return False

    def timeout(self):
        moments = [self.duration_end, self.next_status, self.stage_deadline, self.readiness.next_deadline()]
        moments.append(self.held_until)
        moments.append(self.shm_recheck[0] if self.shm_recheck is not None else None)
        moments.append(self.control.deadline() if self.control is not None else None)
        moments.append(self.containment.before_sleep())
        moments += [node.restart_at for node in self.nodes if node.state == "backoff"]
        moments = [moment for moment in moments if moment is not None]
        now = time.monotonic()
        timeout = max(0.0, min(moments) - now) if moments else None
        if any(node.state == "stopping" and node.pid is None for node in self.nodes):  # what it left is dying
            timeout = LEFTOVER_POLL_S if timeout is None else min(timeout, LEFTOVER_POLL_S)
        if self.requests:  # taken while the loop did not sleep (a wait for the node starter drains the wakeup)
            timeout = 0.0
        return timeout

    def wait(self, timeout):
        """Sleep until a signal arrives, a registered fd is ready, or `timeout` passes."""
        self.poller.wait(timeout)

    def drain_wakeup(self):
        try:
            while os.read(self.wakeup, 4096):
                pass
        except BlockingIOError:
            pass

    def on_timers(self):
        if self.control is not None:
            self.control.poll()
        now = time.monotonic()
        self.containment.poll(now)
        if self.duration_end is not None and now >= self.duration_end:
            self.duration_end = None
            self.request_stop(f"duration of {self.options.duration} s elapsed")
        if self.stage_deadline is not None and now >= self.stage_deadline:
            self.escalate()
        self.start_held(now)
        if self.shm_recheck is not None and now >= self.shm_recheck[0]:
            _, since, looks = self.shm_recheck
            self.remove_abandoned_shm(since)
            looks += 1
            self.shm_recheck = (now + SHM_RECHECKS_S[looks], since, looks) if looks < len(SHM_RECHECKS_S) else None
        for node in self.nodes:
            if node.state == "backoff" and now >= node.restart_at:
                if node.alive():  # what it left behind (killed when it ended) is not gone yet
                    node.processes.kill()
                    node.restart_at = now + LEFTOVER_POLL_S
                    continue
                node.restart_at = None
                self.launch(node)
        self.readiness.on_timer(now, self.stopping)  # after launches: a CUSTOM program is ready as it starts
        if self.next_status is not None and now >= self.next_status:
            self.next_status = now + self.options.status_interval
            self.print_status(now)

    def print_status(self, now):
        counts = {}
        for node in self.nodes:
            counts[node.state] = counts.get(node.state, 0) + 1
        log("supervisor", "status: " + ", ".join(f"{count} {state}" for state, count in sorted(counts.items())))
        for node in self.nodes:
            log(node.name, node.status_line(now))
