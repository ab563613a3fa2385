"""One node: its launch command, environment, process and restart bookkeeping."""

import os

from joshua_codegen.supervisor.build import running_build
from joshua_codegen.supervisor.common import executable_file, find_program, group_alive, log
from joshua_codegen.supervisor.node_processes import NODE_MARK_VARIABLE, node_mark
from joshua_codegen.supervisor.policy import (
    CPP_FALLBACK_WARNING,
    RESTART_DELAY_INITIAL_S,
    STOP_EXTENSION_MAX_S,
)
from joshua_codegen.supervisor.robot import ROBOT


class Node:
    """One node: how to launch it, its current process, and its restart bookkeeping."""

    def __init__(self, spec, python, build=None):
        self.spec = spec
        self.name = spec["name"]
        self.python = python
        self.build = build or running_build()  # the Build its files are in (a reload moves it to the new one)
        self.pid = None  # the node's main process while it runs
        self.pgid = None  # its process group while any member may be alive
        self.processes = None  # everything it started (a NodeCgroup or NodeDescendants), set before its launch
        self.state = "pending"  # pending, running, backoff, finished, failed, stopping, stopped
        self.restarts = (
            0  # restarts its restart policy made (counted again from 0 after a run of RESTART_RESET_AFTER_S)
        )
        self.manual_restarts = 0  # restarts asked for over the control socket
        self.delay = RESTART_DELAY_INITIAL_S
        self.restart_at = None
        self.started_at = None
        self.started_at_wall = None  # time.time() at launch: files it created are not older
        self.backend = ""
        self.last_exit = ""
        self.warned_fallback = False
        self.ready = False  # it said READY=1 since its last start (a CUSTOM node: it started); see notify.py
        self.ready_deadline = None  # when it is warned about for not being ready
        self.status_text = ""  # its last STATUS= notification
        self.stop_requested = False  # stopped over the control socket: no restart until started again
        self.stop_extension_limit = None  # since its SIGINT: the latest end of the more time it may ask for
        self.stop_extended_until = None  # since its SIGINT: it asked for more time to stop until then (notify.py)
        self.input_marks = {}  # the file_mark of each of its inputs as it last launched (reload_plan.py)
        self.environment = self.make_environment()

    def make_environment(self):
        env = dict(os.environ)
        env[ROBOT["fastdds_profile_variable"]] = self.build.path(self.spec["fastdds_profile"])
        env.update(self.build.robot["env"])
        env.update(self.spec["env"])
        env[NODE_MARK_VARIABLE] = node_mark(os.getpid(), self.name)
        return env

    def rebase(self, spec, build):
        """Run as `spec` of `build` from its next launch on (a reload)."""
        self.spec = spec
        self.build = build
        self.environment = self.make_environment()

    def entrypoint(self):
        return self.build.path(self.spec["entrypoint"])

    def cpp_binary(self):
        if not self.spec["cpp_binary"]:
            return None
        return os.path.join(self.build.path(self.build.robot["cpp_bin_dir"]), self.spec["cpp_binary"])

    def custom_program(self):
        executable = self.spec["executable"]
        if "/" in executable:
            return os.path.abspath(executable)
        return find_program(executable, self.environment.get("PATH", os.defpath))

    def runs_cpp(self):
        binary = self.cpp_binary()
        return binary is not None and executable_file(binary)

    def runs_python(self):
        """Whether its next launch runs its Python entrypoint."""
        return self.spec["kind"] != "custom" and not self.runs_cpp()

    def command(self):
        """(argv, backend) chosen at launch: the C++ binary when it is executable, else Python."""
        binary = self.cpp_binary()
        if binary is not None:
            if executable_file(binary):
                return [binary, *self.spec["cpp_args"]], "C++"
            if not self.warned_fallback:
                log(self.name, CPP_FALLBACK_WARNING.format(binary=binary))
                self.warned_fallback = True
        if self.spec["kind"] == "custom":
            return [self.custom_program() or self.spec["executable"], *self.spec["args"]], "custom"
        return [self.python, self.entrypoint()], "Python"

    def sigint_sent(self, now):
        """Its stop began with SIGINT: from now on it may ask for more time before SIGTERM (notify.py)."""
        self.stop_extension_limit = now + STOP_EXTENSION_MAX_S
        self.stop_extended_until = None

    def stop_held(self, now):
        """Whether it asked for more time to stop and that time has not run out (its SIGTERM waits)."""
        return self.stop_extended_until is not None and now < self.stop_extended_until

    def alive(self):
        """Whether anything it started may still run: its process, its process group, its cgroup's or
        tracked processes. A node is stopped only once this is False."""
        if self.pid is not None or (self.pgid is not None and group_alive(self.pgid)):
            return True
        return self.processes is not None and self.processes.alive()

    def status_line(self, now):
        if self.state == "running":
            return (
                f"running pid {self.pid} for {now - self.started_at:.1f} s, {self.backend}, "
                f"{'ready' if self.ready else 'not ready yet'}, {self.restarts} restarts"
                + (f", {self.manual_restarts} asked for" if self.manual_restarts else "")
            )
        if self.state == "backoff":
            return f"restarting in {max(0.0, self.restart_at - now):.2f} s ({self.last_exit})"
        return f"{self.state}" + (f" ({self.last_exit})" if self.last_exit else "")
