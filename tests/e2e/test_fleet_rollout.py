"""Fleet rollouts for real: `joshua-fleet deploy` runs the generated playbooks with ansible-playbook over SSH to
three robots, each a network namespace with Debian's sshd and a private /opt/joshua, running a mock robot
through supervisor.py (start method `supervisor`: no systemd here).

A canary whose release fails its health gate is rolled back and stops the rollout; a tampered or unsigned
release is refused before anything of it runs; `joshua-fleet rollback` goes back; an unreachable robot and a
full disk are each reported in one line with the step that failed.
"""

import hashlib
import json
import shutil
import sys
from pathlib import Path

import pytest

from testsupport.joshuac_cli import joshuac
from testsupport.ssh_robots import SshFleet, ssh_robots

pytestmark = pytest.mark.timeout(1500)

ROBOTS = {"arm_1": "arm1", "arm_2": "arm2", "arm_3": "arm3"}  # fleet robot name -> simulated host
RELEASE_KEY = "/opt/joshua/release.pub"  # on each robot (its private /opt)
MOCK = """robot_config {
  name: "mock"
  mode: MODE_TELEOPERATION
  shutdown { sigint_grace_s: 3 sigterm_grace_s: 1 }
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 20 }
  node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states"
         state_topic: "/follower/joint_states" }
%s}
"""
CRASHING_NODE = '  node { name: "crash" type: CUSTOM executable: "/bin/sh" args: ["-c", "exit 1"] }\n'


def write_fleet(directory: Path, fleet: SshFleet, rate_hz: int, crashing: tuple[str, ...] = ()) -> Path:
    """A fleet file of the three robots (each its own ROS domain, the nodes run by this checkout's interpreter)."""
    (directory / "mock.pbtxt").write_text(MOCK % "")
    (directory / "crashing.pbtxt").write_text(MOCK % CRASHING_NODE)
    robots = []
    for domain, (name, host) in enumerate(ROBOTS.items(), start=31):
        description = "crashing.pbtxt" if name in crashing else "mock.pbtxt"
        robots.append(
            f'  robot {{ name: "{name}" description: "{description}" address: "{fleet.robots[host].address}"\n'
            f'          set: "ros_domain_id={domain}" set: "leader.rate_hz={rate_hz}"\n'
            f'          set: "python_executable={sys.executable}" }}\n'
        )
    path = directory / f"fleet_{rate_hz}.pbtxt"
    path.write_text(
        'fleet_config {\n  name: "lab"\n  start: START_SUPERVISOR\n'
        f'  release_key: "{RELEASE_KEY}"\n' + "".join(robots) + "}\n"
    )
    return path


def build(directory: Path, fleet_file: Path, name: str, key: Path | None) -> Path:
    out = directory / name
    result = joshuac("build", str(fleet_file), "-o", str(out), *(["--sign", str(key)] if key else []))
    assert result.returncode == 0, result.stderr
    return out


def release_of(out: Path, robot: str) -> str:
    return hashlib.sha256((out / "robots" / robot / ".joshuac-stamp").read_bytes()).hexdigest()[:12]


def robot_state(fleet: SshFleet, robot: str) -> dict:
    """What runs on a robot: the release `current` names, and the supervisor's status (or None)."""
    host = fleet.robots[ROBOTS[robot]]
    link = host.run(["readlink", "/opt/joshua/current"]).stdout.strip()
    status = host.run(
        [sys.executable, "/opt/joshua/current/supervisor.py", "ctl", "--control-socket",
         f"/opt/joshua/run/{robot}.sock", "status", "--json"]
    )  # fmt: skip
    pid = host.run(["cat", "/opt/joshua/run/supervisor.pid"]).stdout.strip()
    return {
        "current": Path(link).name if link else None,
        "status": json.loads(status.stdout) if status.returncode == 0 else None,
        "pid": pid,
        "releases": sorted(host.run(["ls", "-A", "/opt/joshua/releases"]).stdout.split()),
    }


def assert_ready_on(state: dict, release: str) -> None:
    assert state["current"] == release
    assert state["status"] is not None, "the supervisor does not answer"
    assert state["status"]["run"]["build"][:12] == release
    assert all(node["ready"] for node in state["status"]["nodes"]), state["status"]


def lines_of(output: str, robot: str) -> list[str]:
    return [line for line in output.splitlines() if line.startswith(f"joshua-fleet: {robot}: ")]


def test_canary_fails_its_gate_and_is_rolled_back_tampered_and_unsigned_releases_never_run(tmp_path):
    key = tmp_path / "release.key"
    assert joshuac("keygen", str(key)).returncode == 0
    with ssh_robots(tmp_path, list(ROBOTS.values())) as fleet:
        for host in fleet.robots.values():
            host.write(RELEASE_KEY, (tmp_path / "release.key.pub").read_bytes())
        first = build(tmp_path, write_fleet(tmp_path, fleet, 20), "out1", key)
        done = fleet.deploy(["deploy", str(first), "--canary", "1"])
        assert done.returncode == 0, done.stdout + done.stderr
        before = {}
        for robot in ROBOTS:
            [line] = lines_of(done.stdout, robot)
            assert f"release {release_of(first, robot)}: ready: 2 of 2 nodes ready" in line
            before[robot] = robot_state(fleet, robot)
            assert_ready_on(before[robot], release_of(first, robot))

        # Release 2: arm_1, the canary, has a node that exits 1 at start. Its gate fails, it goes back to
        # release 1 (started and ready again), and the others are never touched.
        second = build(tmp_path, write_fleet(tmp_path, fleet, 25, crashing=("arm_1",)), "out2", key)
        done = fleet.deploy(["deploy", str(second), "--canary", "1"])
        assert done.returncode == 1, done.stdout + done.stderr
        [line] = lines_of(done.stdout, "arm_1")
        assert line.startswith("joshua-fleet: arm_1: gate: "), line
        assert "crash" in line and f"rolled back to {release_of(first, 'arm_1')}" in line, line
        assert_ready_on(robot_state(fleet, "arm_1"), release_of(first, "arm_1"))
        for robot in ("arm_2", "arm_3"):
            assert lines_of(done.stdout, robot) == [
                f"joshua-fleet: {robot}: not started: the rollout stopped: canary arm_1 failed"
            ]
            after = robot_state(fleet, robot)
            assert_ready_on(after, release_of(first, robot))
            assert after["pid"] == before[robot]["pid"] and after["releases"] == before[robot]["releases"]

        # Release 3, signed; a copy with one file of arm_2's release changed after signing, and arm_3's
        # signature removed. Both are refused at the verify step; nothing of them stays on the robots.
        third = build(tmp_path, write_fleet(tmp_path, fleet, 30), "out3", key)
        tampered = tmp_path / "out3-tampered"
        shutil.copytree(third, tampered)
        with open(tampered / "robots/arm_2/nodes/leader.py", "a") as entrypoint:
            entrypoint.write("import os; os.system('touch /opt/joshua/owned')\n")
        (tampered / "robots/arm_3/.joshuac-stamp.sig").unlink()
        done = fleet.deploy(["deploy", str(tampered), "--limit", "arm_2,arm_3", "--canary", "0", "--on-failure",
                             "continue"])  # fmt: skip
        assert done.returncode == 1, done.stdout + done.stderr
        assert lines_of(done.stdout, "arm_2") == [
            "joshua-fleet: arm_2: verify: nodes/leader.py differs from the release's .joshuac-stamp (signed)"
        ]
        [line] = lines_of(done.stdout, "arm_3")
        assert line.startswith("joshua-fleet: arm_3: verify: the release is not signed"), line
        for robot in ("arm_2", "arm_3"):
            after = robot_state(fleet, robot)
            assert_ready_on(after, release_of(first, robot))
            assert after["pid"] == before[robot]["pid"] and after["releases"] == before[robot]["releases"]
        assert fleet.robots["arm2"].run(["test", "-e", "/opt/joshua/owned"]).returncode == 1

        # The untouched release 3 goes to arm_3; `joshua-fleet rollback arm_3` takes it back to release 1.
        done = fleet.deploy(["deploy", str(third), "--limit", "arm_3"])
        assert done.returncode == 0, done.stdout + done.stderr
        assert_ready_on(robot_state(fleet, "arm_3"), release_of(third, "arm_3"))
        done = fleet.deploy(["rollback", "arm_3"])
        assert done.returncode == 0, done.stdout + done.stderr
        [line] = lines_of(done.stdout, "arm_3")
        assert f"rolled back from {release_of(third, 'arm_3')} to {release_of(first, 'arm_3')}" in line, line
        assert_ready_on(robot_state(fleet, "arm_3"), release_of(first, "arm_3"))


def test_unreachable_robot_and_full_disk_reported_one_line_each_with_the_step(tmp_path):
    with ssh_robots(tmp_path, list(ROBOTS.values()), without_sshd=("arm1",), opt_sizes={"arm2": "8m"}) as fleet:
        out = build(tmp_path, write_fleet(tmp_path, fleet, 20), "out", None)
        done = fleet.deploy(["deploy", str(out), "--canary", "0", "--on-failure", "continue"])
        assert done.returncode == 1, done.stdout + done.stderr
        [line] = lines_of(done.stdout, "arm_1")
        assert line.startswith("joshua-fleet: arm_1: connect: ") and "port 22" in line, line
        [line] = lines_of(done.stdout, "arm_2")
        assert line.startswith("joshua-fleet: arm_2: copy: /opt/joshua/releases has "), line
        assert "MiB free, the release needs" in line, line
        [line] = lines_of(done.stdout, "arm_3")
        assert "ready: 2 of 2 nodes ready" in line, line
        assert fleet.robots["arm2"].run(["test", "-e", "/opt/joshua/current"]).returncode == 1
        assert_ready_on(robot_state(fleet, "arm_3"), release_of(out, "arm_3"))


DESCRIBED_ADDRESSES = ("10.0.0.2", "10.0.0.4")  # the split robot's own host addresses, which the fleet replaces
SPLIT = """robot_config {
  name: "split"
  mode: MODE_TELEOPERATION
  shutdown { sigint_grace_s: 3 sigterm_grace_s: 1 }
  host { name: "arm" address: "10.0.0.2" }
  host { name: "pi" address: "10.0.0.4" }
  discovery { server_host: "arm" }
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 20 host: "pi" }
  node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states"
         state_topic: "/follower/joint_states" }
}
"""
ECHO_TIMEOUT_S = 30.0


def test_a_robot_on_two_computers_gets_each_computers_release_at_the_fleets_addresses(tmp_path):
    """A robot split over two computers is two releases, one per computer, each reached at the address the
    fleet gives it. The Discovery Server on arm is the only way the two computers' nodes find each other (every
    process is its client), so the leader's joints reach arm only if pi's release names arm's fleet address."""
    with ssh_robots(tmp_path, ["armhost", "pihost"]) as fleet:
        computers = {"arm": fleet.robots["armhost"], "pi": fleet.robots["pihost"]}
        (tmp_path / "split.pbtxt").write_text(SPLIT)
        hosts = " ".join(
            f'host {{ name: "{name}" address: "{computer.address}" }}' for name, computer in computers.items()
        )
        (tmp_path / "fleet.pbtxt").write_text(
            'fleet_config {\n  name: "lab"\n  start: START_SUPERVISOR\n'
            f'  robot {{ name: "split_1" description: "split.pbtxt" set: "ros_domain_id=37"\n'
            f'          set: "python_executable={sys.executable}"\n          {hosts} }}\n}}\n'
        )
        out = build(tmp_path, tmp_path / "fleet.pbtxt", "out", None)
        done = fleet.deploy(["deploy", str(out)])
        assert done.returncode == 0, done.stdout + done.stderr
        for host, computer in computers.items():
            release_dir = out / "robots/split_1/hosts" / host
            release = hashlib.sha256((release_dir / ".joshuac-stamp").read_bytes()).hexdigest()[:12]
            processes = len(json.loads((release_dir / "manifest.json").read_text())["processes"])
            [line] = lines_of(done.stdout, f"split_1.{host}")
            assert f"release {release}: ready: {processes} of {processes} nodes ready" in line, line
            assert computer.run(["readlink", "/opt/joshua/current"]).stdout.strip().endswith(release)
            status = computer.run(
                [sys.executable, "/opt/joshua/current/supervisor.py", "ctl", "--control-socket",
                 f"/opt/joshua/run/split_1.{host}.sock", "status", "--json"]
            )  # fmt: skip
            assert json.loads(status.stdout)["run"]["build"][:12] == release
            manifest = json.loads(computer.run(["cat", "/opt/joshua/current/manifest.json"]).stdout)
            assert {entry["name"]: entry["address"] for entry in manifest["hosts"]} == {
                name: other.address for name, other in computers.items()
            }
            assert not any(address in json.dumps(manifest) for address in DESCRIBED_ADDRESSES)
        echo = computers["arm"].run(
            [sys.executable, "-m", "joshua_runtime.tools.topic_cli", "--robot", "/opt/joshua/current", "echo",
             "/leader/joint_states", "--once", "--timeout", str(ECHO_TIMEOUT_S)],
            timeout=ECHO_TIMEOUT_S * 2,
        )  # fmt: skip
        assert echo.returncode == 0, echo.stdout + echo.stderr
        assert "position:" in echo.stdout, echo.stdout
