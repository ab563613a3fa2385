"""One run of a generated playbook (ansible-playbook) over some robots, and each robot's outcome.

The playbooks write one JSON outcome per robot into `joshua_report_dir`; a robot without one (its connection
was lost during the run, or ansible-playbook itself failed) gets an outcome from ansible's output. Ansible's
whole output goes to the rollout's log file.
"""

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from joshua_runtime.errors import SettingsError
from joshua_runtime.rollout.inventory import Inventory, Robot

# Ansible settings a rollout uses unless the environment says otherwise: plain text for the log, and one
# SSH round trip per module (pipelining).
ANSIBLE_DEFAULTS = {"ANSIBLE_NOCOLOR": "1", "ANSIBLE_PIPELINING": "1", "ANSIBLE_RETRY_FILES_ENABLED": "0"}
_UNREACHABLE = re.compile(r"^fatal: \[(?P<robot>[^\]]+)\]: UNREACHABLE! => (?P<result>\{.*\})\s*$", re.MULTILINE)


@dataclass(frozen=True)
class Outcome:
    robot: str
    ok: bool
    step: str  # the step that failed: connect, copy, verify, install, switch, gate, rollback
    message: str  # the ready line, or the one-line reason
    rolled_back_to: str = ""  # the release the robot went back to after a failure
    rollback_message: str = ""
    finished: float | None = None  # when its last step ended (seconds since the epoch)

    def line(self, release: str, seconds: float) -> str:
        """`arm_1: release 3a7d1c09b2e4: ready: ... (12.3 s)` or `arm_1: gate: <reason>; rolled back to ...`."""
        if self.ok:
            return f"{self.robot}: release {release}: {self.message} ({seconds:.1f} s)"
        text = f"{self.robot}: {self.step}: {self.message}"
        if self.rolled_back_to:
            text += f"; rolled back to {self.rolled_back_to} ({self.rollback_message.strip('; ')})"
        return text


def ansible_playbook() -> str:
    """ansible-playbook beside this interpreter (its environment), else on PATH."""
    beside = Path(sys.executable).with_name("ansible-playbook")
    found = str(beside) if beside.is_file() else shutil.which("ansible-playbook")
    if found is None:
        raise SettingsError("ansible-playbook is not installed: install joshua-runtime[fleet] (ansible-core)")
    return found


def read_outcome(path: Path) -> Outcome | None:
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
        finished = record.get("finished")
        return Outcome(
            robot=str(record["robot"]),
            ok=bool(record["ok"]),
            step=str(record.get("step") or ""),
            message=" ".join(str(record.get("message") or "").split()),
            rolled_back_to=str(record.get("rolled_back_to") or ""),
            rollback_message=" ".join(str(record.get("rollback_message") or "").split()),
            finished=float(finished) if finished not in (None, "") else None,
        )
    except (OSError, ValueError, KeyError, TypeError):
        return None


def missing_outcome(robot: Robot, output: str, exit_code: int) -> Outcome:
    """What ansible's output says about a robot that left no outcome. Where Ansible's words do not say which
    address and port it could not reach (a connection that broke, rather than one refused), they are added."""
    for match in _UNREACHABLE.finditer(output):
        if match.group("robot") == robot.name:
            try:
                message = json.loads(match.group("result")).get("msg", "unreachable")
            except ValueError:
                message = "unreachable"
            message = " ".join(str(message).split())
            if f"port {robot.port}" not in message:
                message = f"ssh to {robot.address} port {robot.port}: {message}"
            return Outcome(robot.name, False, "connect", message)
    return Outcome(robot.name, False, "ansible", f"ansible-playbook exited {exit_code} without an outcome for it")


def run_playbook(
    inventory: Inventory, playbook: str, robots: list[str], log, extra_vars: dict | None = None
) -> dict[str, Outcome]:
    """Run `playbook` of the fleet over `robots` (all at once); {robot: outcome}. Ansible's output goes to `log`."""
    command_path = ansible_playbook()
    with tempfile.TemporaryDirectory(prefix="joshua-fleet-") as work:
        reports = Path(work, "reports")
        reports.mkdir()
        variables = {"joshua_report_dir": str(reports), "joshua_archive_dir": work, **(extra_vars or {})}
        command = [command_path, "-i", str(inventory.path), str(inventory.playbook(playbook))]
        command += ["--limit", ",".join(robots), "-e", json.dumps(variables)]
        environment = {**ANSIBLE_DEFAULTS, **os.environ}
        done = subprocess.run(
            command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=environment
        )
        output = done.stdout.decode("utf-8", "replace")
        log.write(output)
        log.flush()
        outcomes, computers = {}, {entry.name: entry for entry in inventory.robots}
        for robot in robots:
            found = read_outcome(reports / f"{robot}.json")
            outcomes[robot] = found or missing_outcome(computers[robot], output, done.returncode)
        return outcomes
