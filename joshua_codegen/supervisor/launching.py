"""Launching nodes: forked and exec'd by the supervisor, or forked from the node starter, many at once."""

import os
import shlex
import signal
import time

from joshua_codegen.supervisor.children import child_exec
from joshua_codegen.supervisor.common import PRCTL, log
from joshua_codegen.supervisor.node_processes import CgroupContainment
from joshua_codegen.supervisor.node_starter import NodeStarter
from joshua_codegen.supervisor.policy import HELD_FOR_PYTHON, STARTER_MIN_NODES, STOP_SIGNALS
from joshua_codegen.supervisor.reload_plan import input_marks


class Launching:
    """The Supervisor's launches (a mixin of it): `launch_all` of nodes in one go, `launch` of one."""

    def node_starter(self):
        """A NodeStarter for the Python nodes, where they are STARTER_MIN_NODES at least and each runs in its own
        cgroup (without, its descendants are told apart by their environment at exec) as the supervisor's
        child (a subreaper adopts what the starter forks), unless --no-node-starter."""
        python_nodes = [node for node in self.nodes if node.runs_python() and not node.spec["env"]]
        if (
            self.options.no_node_starter
            or len(python_nodes) < STARTER_MIN_NODES
            or PRCTL is None
            or not isinstance(self.containment, CgroupContainment)
        ):
            return None
        return NodeStarter(self.options.python, python_nodes)

    def launch(self, node):
        self.launch_all([node])

    def launch_all(self, nodes):
        """Launch `nodes`: first those the supervisor forks itself, then those the starter forks (started and
        waited for first, when it is not running yet). A stop asked for meanwhile leaves the rest as they are."""
        commands = {node.name: node.command() for node in nodes}
        forked = [
            node for node in nodes if self.starter is not None and self.starter.serves(node, commands[node.name][0])
        ]
        for node in nodes:
            if node not in forked:
                if self.requests:
                    return
                self.spawn(node, *commands[node.name], pid=None)
        if not forked or (not self.starter.ready(self) and self.requests):
            return
        outputs = {}
        for node in forked:
            try:
                outputs[node.name] = self.output_pipe(node)
            except OSError as exc:
                self.start_failed(node, exc, (None, None))
        forked = [node for node in forked if node.name in outputs]
        asked = self.starter.state == "ready"
        results = [None] * len(forked)
        if asked:
            results = self.starter.launch([(node, outputs[node.name][1]) for node in forked], self.pid)
        for node, result in zip(forked, results):
            if asked and result is None:
                node.processes.kill()  # one the starter forked before it failed would otherwise run twice
            self.spawn(node, *commands[node.name], pid=result, output=outputs[node.name])

    def output_pipe(self, node):
        node_log = self.logs.get(node.name)
        return node_log.open_pipe() if node_log is not None else (None, None)

    def spawn(self, node, argv, backend, pid, output=None):
        """Take the node's process as running: `pid` forked by the starter, an OSError it met, or None: fork and
        exec it here, with its output pipe (`output`, opened here when not given)."""
        node.backend = backend
        node.input_marks = input_marks(node.spec["inputs"])
        read_end, write_end = output or (None, None)
        blocked = STOP_SIGNALS + (signal.SIGCHLD,)
        signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
        try:
            if isinstance(pid, OSError):
                raise pid
            if output is None:
                read_end, write_end = self.output_pipe(node)
            if pid is None:
                pid = node.processes.fork()
                if pid == 0:
                    held = HELD_FOR_PYTHON if backend == "Python" else ()
                    child_exec(argv, node.environment, self.pid, node.processes.join, write_end, held)
        except OSError as exc:  # out of descriptors or processes: a failed start, its restart policy applies
            self.start_failed(node, exc, (read_end, write_end))
            return
        finally:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, blocked)
        if read_end is not None:
            os.close(write_end)
            node_log = self.logs[node.name]
            self.readers[read_end] = lambda: self.read_output(node_log, read_end)
        node.pid = node.pgid = pid
        node.state = "running"
        node.started_at = time.monotonic()
        node.started_at_wall = time.time()
        self.by_pid[pid] = node
        self.guard.track(pid)
        log(node.name, f"started pid {pid} ({node.backend}): {shlex.join(argv)}")
        self.readiness.on_launch(node, node.started_at)

    def start_failed(self, node, exc, output):
        for fd in output:
            if fd is not None:
                os.close(fd)
        log(node.name, f"cannot start: {exc}")
        node.last_exit = f"start failed: {exc}"
        self.after_exit(node, failed=True, ran_for=0.0)

    def read_output(self, node_log, fd):
        if not node_log.read(fd):
            del self.readers[fd]
            os.close(fd)
