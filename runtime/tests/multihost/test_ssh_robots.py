"""The robots of testsupport/ssh_robots.py: each fleet's deployer reaches its own robots, also beside another fleet."""

import subprocess

from testsupport.ssh_robots import VENV_BIN, SshFleet, ssh_robots

ROBOT = "arm"
MARK = "/opt/which-fleet"  # in each robot's private /opt


def ansible_raw(fleet: SshFleet, command: str) -> subprocess.CompletedProcess:
    """`ansible -m raw` on the fleet's robot, from its deployer, with the connection sharing a rollout uses."""
    return fleet.deployer.run(
        [VENV_BIN / "ansible", "all", "-i", f"{fleet.robots[ROBOT].address},", "-m", "raw", "-a", command],
        cwd=fleet.directory,
        env=fleet.environment(),
        capture_output=True,
        text=True,
    )


def test_two_fleets_at_once_each_reach_their_own_robot_at_the_same_address(tmp_path):
    (tmp_path / "first").mkdir()
    (tmp_path / "second").mkdir()
    with ssh_robots(tmp_path / "first", [ROBOT]) as first, ssh_robots(tmp_path / "second", [ROBOT]) as second:
        assert first.robots[ROBOT].address == second.robots[ROBOT].address  # each on its own switch
        for fleet, name in ((first, "first"), (second, "second")):
            fleet.robots[ROBOT].write(MARK, f"{name}\n".encode())
        # The first fleet's SSH connection outlives its ansible run (ControlPersist) while the second's runs.
        for fleet, name in ((first, "first"), (second, "second"), (first, "first")):
            done = ansible_raw(fleet, f"cat {MARK}")
            assert done.returncode == 0, done.stdout + done.stderr
            [_, said, *_] = done.stdout.splitlines()  # "<address> | CHANGED | rc=0 >>", then what cat printed
            assert said == name, done.stdout
