"""Run a built robot's supervisor.py in the foreground, for `joshuac run`, and tell the dashboard's address."""

import ctypes
import signal
import subprocess
import sys
from pathlib import Path

FORWARDED_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
PR_SET_PDEATHSIG = 1
EXIT_SIGNALED_BASE = 128  # a supervisor killed by signal N makes the command exit 128 + N


def _own_group_and_die_with_parent() -> None:
    """In the supervisor's child before exec: leave the terminal's process group (signals reach it
    only through this process, once each) and get SIGTERM, so the cascade runs, if this process dies."""
    import os

    os.setpgid(0, 0)
    try:
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    except (OSError, AttributeError):
        pass


def run_supervisor(out_dir: Path, extra_args: list[str]) -> int:
    """Run OUT/supervisor.py with this interpreter (so joshua_runtime is importable by the nodes),
    forward SIGINT/SIGTERM/SIGHUP to it, and return its exit code."""
    command = [sys.executable, str(Path(out_dir) / "supervisor.py"), *extra_args]
    process = subprocess.Popen(command, preexec_fn=_own_group_and_die_with_parent)  # noqa: PLW1509

    def forward(number, _frame):
        if process.poll() is None:
            process.send_signal(number)

    previous = {number: signal.signal(number, forward) for number in FORWARDED_SIGNALS}
    try:
        code = process.wait()
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
    return EXIT_SIGNALED_BASE - code if code < 0 else code


def dashboard_address(config) -> str | None:
    """The address of the robot's dashboard page carrying its access token (the token file is created
    now when absent, where the supervisor's dashboard will read it), or None without a dashboard block.
    Raises joshua_core.dashboard_token.TokenFileError."""
    from joshua_codegen.supervisor.control_socket import default_control_socket
    from joshua_core.dashboard import DEFAULT_BIND, DEFAULT_PORT, page_url
    from joshua_core.dashboard_token import load_or_create_token, token_path

    if not config.HasField("dashboard"):
        return None
    dashboard = config.dashboard
    port = dashboard.port if dashboard.HasField("port") else DEFAULT_PORT
    token = load_or_create_token(token_path(Path(default_control_socket(config.name))))
    return f"{page_url(dashboard.bind or DEFAULT_BIND, port)}#token={token}"
