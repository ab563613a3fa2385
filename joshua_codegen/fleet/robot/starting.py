"""Stopping and starting a robot on its current release: its systemd units, or supervisor.py in the background."""

import os
import shutil
import signal
import subprocess
import time

from layout import run

STOP_TIMEOUT_S = 60.0  # the supervisor's SIGINT -> SIGTERM -> SIGKILL cascade ends well within this
STOP_POLL_S = 0.1


def supervisor_pid(layout: dict) -> int | None:
    """The running supervisor's pid from run/supervisor.pid, when that process is a supervisor.py."""
    try:
        with open(os.path.join(layout["run"], "supervisor.pid"), encoding="ascii") as file:
            pid = int(file.read().strip())
        with open(f"/proc/{pid}/cmdline", "rb") as file:
            return pid if b"supervisor.py" in file.read() else None
    except (OSError, ValueError):
        return None


def stop(args, layout: dict) -> None:
    if args.start == "systemd":
        target = f"joshua-{args.robot}.target"
        if os.path.exists(os.path.join(args.unit_dir, target)):  # none before the robot's first release
            run(["systemctl", "stop", target], f"systemctl stop {target}")
        return
    pid = supervisor_pid(layout)
    if pid is None:
        return
    os.kill(pid, signal.SIGTERM)
    deadline = time.monotonic() + STOP_TIMEOUT_S
    while os.path.exists(f"/proc/{pid}") and supervisor_pid(layout) == pid:
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            break
        time.sleep(STOP_POLL_S)


def install_units(args, layout: dict) -> None:
    """The current release's units in /etc/systemd/system (this robot's older ones removed), enabled."""
    units_dir = os.path.join(layout["current"], "systemd")
    wanted = sorted(os.listdir(units_dir))
    prefix = f"joshua-{args.robot}"
    for name in os.listdir(args.unit_dir):
        if (name == f"{prefix}.target" or name.startswith(f"{prefix}-")) and name not in wanted:
            os.unlink(os.path.join(args.unit_dir, name))
    for name in wanted:
        shutil.copyfile(os.path.join(units_dir, name), os.path.join(args.unit_dir, name))
    run(["systemctl", "daemon-reload"], "systemctl daemon-reload")
    run(["systemctl", "enable", f"{prefix}.target"], f"systemctl enable {prefix}.target")


def start(args, layout: dict) -> None:
    if args.start == "systemd":
        install_units(args, layout)
        run(["systemctl", "start", f"joshua-{args.robot}.target"], f"systemctl start joshua-{args.robot}.target")
        return
    command = [args.python, "-S", os.path.join(layout["current"], "supervisor.py")]  # standard library only
    command += ["--control-socket", os.path.join(layout["run"], f"{args.control or args.robot}.sock")]
    command += ["--log-dir", layout["logs"]]
    with open(os.path.join(layout["logs"], "supervisor.log"), "ab") as log:
        process = subprocess.Popen(
            command, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT, start_new_session=True
        )
    with open(os.path.join(layout["run"], "supervisor.pid"), "w", encoding="ascii") as file:
        file.write(f"{process.pid}\n")


def start_unless_running(args, layout: dict) -> None:
    if args.start == "supervisor" and supervisor_pid(layout) is not None:
        return
    start(args, layout)
