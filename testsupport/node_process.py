"""A node run in its own process the way a generated entrypoint runs it: `run_node(SETTINGS)`.

Shared by the runtime test suites (importable from every test as testsupport.node_process).
"""

import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

from joshua_codegen.supervisor import policy


def default_signals() -> None:
    """In the child before exec: the signals supervisor.py resets at their defaults, its stop signals unblocked,
    as it starts a node. A test worker's process may hold them ignored or blocked after earlier tests, and both
    last across exec."""
    for number in policy.RESET_IN_CHILD:
        signal.signal(number, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, policy.STOP_SIGNALS)


def start_python(env: dict, *args: str, stderr=subprocess.PIPE) -> subprocess.Popen:
    """`python -c ARGS...` started as the supervisor starts a node (default_signals), its output piped as text
    (its stderr to `stderr` when given a file)."""
    return subprocess.Popen(
        [sys.executable, "-c", *args],
        env=env,
        stdout=subprocess.PIPE,
        stderr=stderr,
        text=True,
        preexec_fn=default_signals,
    )


NODE_STOP_TIMEOUT_S = 5.0
SHUTDOWN_CONTRACT_S = 0.5  # every node exits within this after SIGINT/SIGTERM (DESIGN.md)
NODE_EXIT_TIMEOUT_S = 30.0  # a cold rclpy process on a busy 2-core machine


def stop_process(process: subprocess.Popen, signum=signal.SIGINT) -> tuple[int, float, str]:
    """Send `signum` (if still running); return (exit code, seconds until exit, stderr). Kills it after a timeout."""
    sent = time.monotonic()
    if process.poll() is None:
        process.send_signal(signum)
    try:
        _, stderr = process.communicate(timeout=NODE_STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        _, stderr = process.communicate()
    return process.returncode, time.monotonic() - sent, stderr


class NodeProcess:
    """One node, from its settings dict, in `python -c "...run_node(SETTINGS)"` with `env`.

    With `stderr_path` its stderr goes to that file, which a test can read while the node runs.
    """

    stderr_path: Path | None = None

    def __init__(self, settings: dict, env: dict, stderr_path: Path | None = None):
        code = f"import sys\nfrom joshua_runtime.entrypoint import run_node\nsys.exit(run_node({settings!r}))\n"
        self.stderr_path = stderr_path
        command = [sys.executable, "-c", code]
        if stderr_path is None:
            self.process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        else:
            with open(stderr_path, "w") as stderr:
                self.process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=stderr, text=True)

    def stderr_text(self) -> str:
        """What the node wrote to stderr so far (only with `stderr_path`)."""
        return self.stderr_path.read_text(errors="replace") if self.stderr_path.exists() else ""

    def read_stderr_until(self, text: str, timeout: float = NODE_EXIT_TIMEOUT_S) -> str:
        """Read the node's piped stderr until `text` appears; what was read (gone from what `stop` returns).
        Fails with it when the node exits first or time runs out."""
        deadline, seen = time.monotonic() + timeout, b""
        stderr = self.process.stderr.fileno()
        while text.encode() not in seen:
            remaining = deadline - time.monotonic()
            assert remaining > 0, f"no {text!r} from the node within {timeout} s: {seen.decode(errors='replace')}"
            if select.select([stderr], [], [], remaining)[0]:
                chunk = os.read(stderr, 4096)
                assert chunk, f"the node exited before {text!r}: {seen.decode(errors='replace')}"
                seen += chunk
        return seen.decode(errors="replace")

    def stop(self, signum=signal.SIGINT) -> tuple[int, float, str]:
        """Send `signum`; return (exit code, seconds until exit, stderr)."""
        code, seconds, stderr = stop_process(self.process, signum)
        return code, seconds, stderr if self.stderr_path is None else self.stderr_text()

    def wait(self, timeout: float = NODE_EXIT_TIMEOUT_S) -> tuple[int, str]:
        """Wait for the process to end by itself; return (exit code, stderr)."""
        _, stderr = self.process.communicate(timeout=timeout)
        return self.process.returncode, stderr if self.stderr_path is None else self.stderr_text()

    def failure(self) -> str:
        """Why the process is gone (exit code and stderr), or that it still runs."""
        if self.process.poll() is None:
            return "process still running"
        stderr = self.process.communicate()[1]
        return f"exit code {self.process.returncode}: {stderr if self.stderr_path is None else self.stderr_text()}"

    def kill(self) -> None:
        """End it if it still runs, reap it and close its pipes."""
        if self.process.poll() is None:
            self.process.kill()
        self.process.communicate()
