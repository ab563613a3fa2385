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


def run_supervisor(out_dir: Path, extra_args: list[str], follow=None) -> int:
    """Run OUT/supervisor.py with this interpreter (so joshua_runtime is importable by the nodes),
    forward SIGINT/SIGTERM/SIGHUP to it, and return its exit code. `follow(process)`, when given, runs
    while it does and returns its exit status (`joshuac run --watch`: watch.py)."""
    command = [sys.executable, str(Path(out_dir) / "supervisor.py"), *extra_args]
    process = subprocess.Popen(command, preexec_fn=_own_group_and_die_with_parent)  # noqa: PLW1509

    def forward(number, _frame):
        if process.poll() is None:
            process.send_signal(number)

    previous = {number: signal.signal(number, forward) for number in FORWARDED_SIGNALS}
    try:
        code = process.wait() if follow is None else follow(process)
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
    return EXIT_SIGNALED_BASE - code if code < 0 else code


class HostChoiceError(Exception):
    """`--host` does not fit the description: missing for a robot on several hosts, or naming no host."""


def host_directory(robot, out_dir: Path, host: str | None) -> Path:
    """The directory of the build whose supervisor runs: OUT itself, or OUT/hosts/HOST for one host of a
    robot on several. Raises HostChoiceError."""
    from joshua_codegen.render import host_path

    names = [h.name for h in robot.hosts]
    if not names:
        if host is not None:
            raise HostChoiceError(f"--host {host}: robot {robot.name} declares no hosts; run it without --host")
        return out_dir
    if host is None:
        raise HostChoiceError(
            f"robot {robot.name} runs on several hosts ({', '.join(names)}): run one with --host NAME on its computer"
        )
    if host not in names:
        raise HostChoiceError(f"--host {host}: robot {robot.name} has no such host (hosts: {', '.join(names)})")
    return out_dir / host_path(host)


def dashboard_address(config, host: str | None = None) -> str | None:
    """The address of the robot's dashboard page carrying its access token (the token file is created
    now when absent, where the supervisor's dashboard will read it), or None without a dashboard block
    (or when the dashboard runs on another host than `host`).
    Raises joshua_core.dashboard_token.TokenFileError."""
    from joshua_codegen.placement import service_host
    from joshua_codegen.supervisor.control_socket import control_name, default_control_socket
    from joshua_core.dashboard import DEFAULT_BIND, DEFAULT_PORT, page_url
    from joshua_core.dashboard_token import load_or_create_token, token_path

    if not config.HasField("dashboard") or (host and service_host(config, "dashboard") != host):
        return None
    dashboard = config.dashboard
    port = dashboard.port if dashboard.HasField("port") else DEFAULT_PORT
    socket_name = control_name({"name": config.name, "host": host or ""})
    token = load_or_create_token(token_path(Path(default_control_socket(socket_name))))
    return f"{page_url(dashboard.bind or DEFAULT_BIND, port)}#token={token}"
