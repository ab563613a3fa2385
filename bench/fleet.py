"""Fleet figures: a signed, canaried rollout to robots over SSH, and the fleet plane with 50 robots at 10 Hz.

    .venv/bin/python bench/fleet.py [--quick]        (as root: the robots are network namespaces)

Rollout: three robots (two with --quick), each a network namespace with its own sshd and private /opt
(testsupport/ssh_robots.py), get a signed release of a mock robot (two MOCK nodes, start method
`supervisor`) from `joshua-fleet deploy OUT --canary 1`, then (not with --quick) a second release. Printed: each
rollout's time, and each robot's, from the start of its batch to its outcome (the canary's batch first),
beside the floor of the same machine: one `ansible-playbook` run of a playbook doing nothing but reach the
same robots (`ping`).

Fleet plane: bench/support/fleet_plane.py (50 robots; with --quick 2, windows of 1 s, the loaded one until
the page showed one change, and 2 withdrawals), and how soon a robot whose dashboard stops is listed offline.
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))
from support import fleet_plane  # noqa: E402

from testsupport.joshuac_cli import joshuac  # noqa: E402
from testsupport.ssh_robots import VENV_BIN, ssh_robots  # noqa: E402

ROBOTS, QUICK_ROBOTS = 3, 2
PLANE_ROBOTS, QUICK_PLANE_ROBOTS = 50, 2
WINDOW_S, QUICK_WINDOW_S = 20.0, 1.0
MOCK = """robot_config {
  name: "mock"
  mode: MODE_TELEOPERATION
  shutdown { sigint_grace_s: 3 sigterm_grace_s: 1 }
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: %d }
  node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states"
         state_topic: "/follower/joint_states" }
}
"""
PING = "- hosts: all\n  gather_facts: false\n  tasks:\n    - ansible.builtin.ping:\n"
ROBOT_LINE = re.compile(r"^joshua-fleet: (\S+): release \S+: .* \((\d+\.\d+) s\)$", re.MULTILINE)
TOTAL_LINE = re.compile(r"robots on their new release in (\d+\.\d+) s")


def write_fleet(directory: Path, addresses: list[str], rate_hz: int) -> Path:
    (directory / "mock.pbtxt").write_text(MOCK % rate_hz)
    robots = "".join(
        f'  robot {{ name: "arm_{i + 1}" description: "mock.pbtxt" address: "{address}" set: "ros_domain_id={41 + i}"\n'
        f'          set: "python_executable={sys.executable}" }}\n'
        for i, address in enumerate(addresses)
    )
    path = directory / f"fleet_{rate_hz}.pbtxt"
    path.write_text(
        f'fleet_config {{\n  name: "bench"\n  start: START_SUPERVISOR\n  release_key: "/opt/joshua/release.pub"\n{robots}}}\n'
    )
    return path


def rollout(robots: int, releases: int) -> None:
    with tempfile.TemporaryDirectory(prefix="bench-rollout-") as work:
        directory = Path(work)
        os.environ["XDG_STATE_HOME"] = str(directory / "state")  # joshua-fleet's state and logs stay here
        joshuac("keygen", directory / "release.key", check=True)
        names = [f"arm{i + 1}" for i in range(robots)]
        with ssh_robots(directory, names) as fleet:
            for host in fleet.robots.values():
                host.write("/opt/joshua/release.pub", (directory / "release.key.pub").read_bytes())
            (directory / "ping.yml").write_text(PING)
            out = directory / "out1"
            addresses = [fleet.robots[name].address for name in names]
            joshuac("build", write_fleet(directory, addresses, 20), "-o", out, "--sign", directory / "release.key",
                    check=True)  # fmt: skip
            started = time.monotonic()
            floor = fleet.deployer.run(
                [str(VENV_BIN / "ansible-playbook"), "-i", str(out / "ansible/inventory.yml"), str(directory / "ping.yml")],
                cwd=directory, env=fleet.environment(), capture_output=True, text=True,
            )  # fmt: skip
            floor_s = time.monotonic() - started
            if floor.returncode != 0:
                raise RuntimeError(f"ansible-playbook ping failed:\n{floor.stdout}")
            for number, rate in enumerate((20, 25, 30)[:releases], start=1):
                out = directory / f"out{number}"
                if number > 1:
                    joshuac("build", write_fleet(directory, addresses, rate), "-o", out, "--sign",
                            directory / "release.key", check=True)  # fmt: skip
                done = fleet.deploy(["deploy", str(out), "--canary", "1"])
                if done.returncode != 0:
                    raise RuntimeError(f"joshua-fleet deploy failed:\n{done.stdout}{done.stderr}")
                total = float(TOTAL_LINE.search(done.stdout).group(1))
                each = ", ".join(f"{name} {seconds} s" for name, seconds in ROBOT_LINE.findall(done.stdout))
                print(
                    f"rollout {number} of {robots} robots (canary 1, signed): {total:.1f} s ({total / floor_s:.1f}x one "
                    f"ansible-playbook ping of them, {floor_s:.1f} s); per robot, from its batch's start: {each}",
                    flush=True,
                )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer robots, shorter windows, one release")
    args = parser.parse_args()
    if os.geteuid() != 0:
        print("bench/fleet.py: the rollout needs root (network namespaces); run it as root", file=sys.stderr)
        sys.exit(2)
    rollout(QUICK_ROBOTS if args.quick else ROBOTS, 1 if args.quick else 2)
    plane = fleet_plane.measure(
        QUICK_PLANE_ROBOTS if args.quick else PLANE_ROBOTS,
        QUICK_WINDOW_S if args.quick else WINDOW_S,
        fleet_plane.QUICK_WITHDRAWALS if args.quick else fleet_plane.WITHDRAWALS,
        fleet_plane.QUICK_PAGE_CHANGES if args.quick else 0,
    )
    print(plane.summary(), flush=True)


if __name__ == "__main__":
    try:
        main()
    except subprocess.CalledProcessError as exc:
        print(f"bench/fleet.py: {exc}\n{exc.stdout}\n{exc.stderr}", file=sys.stderr)
        sys.exit(1)
