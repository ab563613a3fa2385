"""`joshuac build FLEET -o OUT`: one complete, stamped and signed release per robot (per host of a robot on several
computers) and Ansible files that Ansible itself accepts; the same input gives the same bytes."""

import hashlib
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from testsupport.joshuac_cli import joshuac

ANSIBLE_PLAYBOOK = Path(sys.executable).with_name("ansible-playbook")
ARM = """robot_config {
  name: "arm"
  mode: MODE_TELEOPERATION
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" }
}
"""
SPLIT = """robot_config {
  name: "split"
  mode: MODE_TELEOPERATION
  host { name: "arm" address: "10.0.0.2" }
  host { name: "pi" address: "10.0.0.4" }
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" host: "pi" }
  node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" }
}
"""
FLEET = """fleet_config {
  name: "lab"
  start: START_SUPERVISOR
  rollout { canary: 2 batch: 3 health_timeout_s: 30 on_failure: ON_FAILURE_CONTINUE }
  robot { name: "arm_1" description: "arm.pbtxt" address: "10.0.0.11" set: "ros_domain_id=11" }
  robot { name: "arm_2" description: "arm.pbtxt" address: "arm-2.lab" ssh_user: "robot" ssh_port: 2222
          set: "ros_domain_id=12" set: "python_executable=/usr/bin/python3" }
  robot { name: "split_1" description: "split.pbtxt" set: "ros_domain_id=13" host { name: "pi" address: "10.0.1.4" } }
}
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    directory = tmp_path_factory.mktemp("fleet")
    (directory / "arm.pbtxt").write_text(ARM)
    (directory / "split.pbtxt").write_text(SPLIT)
    (directory / "lab.pbtxt").write_text(FLEET)
    assert joshuac("keygen", "release.key", cwd=directory).returncode == 0
    done = joshuac("build", "lab.pbtxt", "-o", "out", "--sign", "release.key", cwd=directory)
    assert done.returncode == 0, done.stderr
    return directory


def stamp_hash(directory: Path) -> str:
    return hashlib.sha256((directory / ".joshuac-stamp").read_bytes()).hexdigest()[:12]


def test_every_release_is_complete_checked_by_its_stamp_and_signed(built):
    out = built / "out"
    releases = [
        out / "robots/arm_1",
        out / "robots/arm_2",
        out / "robots/split_1/hosts/arm",
        out / "robots/split_1/hosts/pi",
    ]
    for release in releases:
        for name in ("supervisor.py", "manifest.json", "install.sh", "wheels/requirements.txt"):
            assert (release / name).is_file(), release / name
        subprocess.run(["sha256sum", "--check", "--quiet", "--strict", ".joshuac-stamp"], cwd=release, check=True)
        verified = subprocess.run(
            ["openssl", "pkeyutl", "-verify", "-pubin", "-inkey", str(built / "release.key.pub"), "-rawin",
             "-in", ".joshuac-stamp", "-sigfile", ".joshuac-stamp.sig"],
            cwd=release, capture_output=True, text=True,
        )  # fmt: skip
        assert verified.returncode == 0, verified.stdout + verified.stderr
    assert (
        "/opt/joshua/current/nodes/leader.py" in (out / "robots/arm_1/systemd/joshua-arm_1-leader.service").read_text()
    )
    subprocess.run(["sha256sum", "--check", "--quiet", "--strict", ".joshuac-stamp"], cwd=out, check=True)


def test_the_inventory_lists_every_computer_in_order_with_its_release_and_the_rollout_settings(built):
    out = built / "out"
    text = (out / "ansible/inventory.yml").read_text()
    loader = type("Loader", (yaml.SafeLoader,), {})
    loader.add_constructor("!unsafe", lambda loader, node: loader.construct_scalar(node))
    group = yaml.load(text, Loader=loader)["all"]["children"]["lab"]  # noqa: S506 (a SafeLoader)
    assert group["vars"]["joshua_start"] == "supervisor" and group["vars"]["joshua_canary"] == 2
    assert (group["vars"]["joshua_batch"], group["vars"]["joshua_health_timeout_s"]) == (3, 30.0)
    assert group["vars"]["joshua_on_failure"] == "continue"
    assert group["vars"]["joshua_release_key"] == "/etc/joshua/release.pub"
    hosts = group["hosts"]
    assert list(hosts) == ["arm_1", "arm_2", "split_1.arm", "split_1.pi"]
    assert hosts["arm_1"]["joshua_release"] == stamp_hash(out / "robots/arm_1")
    assert hosts["arm_1"]["joshua_install"] is True
    assert (hosts["arm_2"]["ansible_host"], hosts["arm_2"]["ansible_user"], hosts["arm_2"]["ansible_port"]) == (
        "arm-2.lab", "robot", 2222
    )  # fmt: skip
    assert hosts["arm_2"]["ansible_become"] is True and hosts["arm_2"]["joshua_install"] is False
    assert (hosts["split_1.pi"]["ansible_host"], hosts["split_1.arm"]["ansible_host"]) == ("10.0.1.4", "10.0.0.2")
    assert hosts["split_1.pi"]["joshua_release"] == stamp_hash(out / "robots/split_1/hosts/pi")
    assert hosts["split_1.pi"]["joshua_control"] == "split_1.pi"
    assert "10.0.1.4" in (out / "robots/split_1/hosts/arm/manifest.json").read_text()


def test_ansible_accepts_the_playbooks(built):
    out = built / "out"
    for playbook in ("deploy.yml", "rollback.yml"):
        done = subprocess.run(
            [str(ANSIBLE_PLAYBOOK), "--syntax-check", "-i", "ansible/inventory.yml", f"ansible/{playbook}"],
            cwd=out, capture_output=True, text=True,
        )  # fmt: skip
        assert done.returncode == 0, done.stdout + done.stderr


def test_the_same_fleet_and_key_give_the_same_bytes_and_the_build_replaces_its_own_output(built):
    again = joshuac("build", "lab.pbtxt", "-o", "again", "--sign", "release.key", cwd=built)
    assert again.returncode == 0, again.stderr
    first = {p.relative_to(built / "out"): p.read_bytes() for p in (built / "out").rglob("*") if p.is_file()}
    second = {p.relative_to(built / "again"): p.read_bytes() for p in (built / "again").rglob("*") if p.is_file()}
    assert first == second
    rebuilt = joshuac("build", "lab.pbtxt", "-o", "again", cwd=built)  # unsigned now, over a signed output
    assert rebuilt.returncode == 0, rebuilt.stderr
    assert not (built / "again/robots/arm_1/.joshuac-stamp.sig").exists()


def test_prefix_does_not_apply_to_a_fleet(built):
    done = joshuac("build", "lab.pbtxt", "-o", "other", "--prefix", "/srv/robot", cwd=built)
    assert done.returncode == 2
    assert "--prefix does not apply" in done.stderr and not (built / "other").exists()
