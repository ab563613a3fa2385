"""Which robots `joshua-fleet deploy` takes, in what batches, and what it says of a robot that left no outcome."""

import pytest

from joshua_runtime.errors import SettingsError
from joshua_runtime.rollout.batches import batches, selected
from joshua_runtime.rollout.inventory import Robot
from joshua_runtime.rollout.playbook import Outcome, missing_outcome

ROBOTS = (
    Robot("arm_1", "arm_1", "10.0.0.11", "a" * 12),
    Robot("arm_2", "arm_2", "10.0.0.12", "b" * 12),
    Robot("split.arm", "split", "10.0.1.2", "c" * 12),
    Robot("split.pi", "split", "10.0.1.4", "d" * 12),
    Robot("cart", "cart", "10.0.0.20", "e" * 12),
)


def names(robots) -> list[str]:
    return [robot.name for robot in robots]


def test_limit_takes_names_and_patterns_and_leaves_out_what_starts_with_an_exclamation_mark():
    assert names(selected(ROBOTS, None)) == names(ROBOTS)
    assert names(selected(ROBOTS, "arm_*,cart")) == ["arm_1", "arm_2", "cart"]
    assert names(selected(ROBOTS, "!arm_2")) == ["arm_1", "split.arm", "split.pi", "cart"]
    assert names(selected(ROBOTS, "split")) == ["split.arm", "split.pi"]
    assert names(selected(ROBOTS, "split.pi")) == ["split.pi"]
    with pytest.raises(SettingsError, match="no robot of the fleet matches 'arm_9'"):
        selected(ROBOTS, "arm_9")


def test_canaries_and_batches_count_robots_each_with_all_its_computers():
    parts = batches(list(ROBOTS), canary=1, batch=2)
    assert [(label, names(part)) for label, part in parts] == [
        ("canary", ["arm_1"]),
        ("batch 1", ["arm_2", "split.arm", "split.pi"]),
        ("batch 2", ["cart"]),
    ]
    assert [label for label, _ in batches(list(ROBOTS), canary=0, batch=10)] == ["batch 1"]
    with pytest.raises(SettingsError):
        batches(list(ROBOTS), canary=1, batch=0)


def test_a_robot_ansible_could_not_reach_is_told_from_ansibles_own_words():
    output = (
        "TASK [gate: every node ready] ***\n"
        'fatal: [arm_2]: UNREACHABLE! => {"changed": false, "msg": "Failed to connect to the host via ssh: '
        'ssh: connect to host 10.0.0.12 port 22: No route to host", "unreachable": true}\n'
    )
    assert missing_outcome(ROBOTS[1], output, 4) == Outcome(
        "arm_2", False, "connect", "Failed to connect to the host via ssh: ssh: connect to host 10.0.0.12 port 22: "
        "No route to host"
    )  # fmt: skip
    assert missing_outcome(ROBOTS[0], output, 4).message == "ansible-playbook exited 4 without an outcome for it"


def test_a_broken_connection_is_told_with_the_address_and_port_ansible_left_out():
    output = (
        'fatal: [arm_1]: UNREACHABLE! => {"changed": false, "msg": "Task failed: Data could not be sent to remote '
        'host \'10.0.0.11\'. Make sure this host can be reached over SSH: [Errno 32] Broken pipe", "unreachable": true}\n'
    )
    assert missing_outcome(ROBOTS[0], output, 4).message == (
        "ssh to 10.0.0.11 port 22: Task failed: Data could not be sent to remote host '10.0.0.11'. "
        "Make sure this host can be reached over SSH: [Errno 32] Broken pipe"
    )


def test_each_robot_ends_with_one_line():
    assert Outcome("arm_1", True, "", "ready: 2 of 2 nodes ready (build aaa), 3.0 s").line("aaa", 12.34) == (
        "arm_1: release aaa: ready: 2 of 2 nodes ready (build aaa), 3.0 s (12.3 s)"
    )
    failed = Outcome("arm_1", False, "gate", "node crash failed", "bbbbbbbbbbbb", "rolled back; ready: 2 of 2")
    assert (
        failed.line("aaa", 1.0)
        == "arm_1: gate: node crash failed; rolled back to bbbbbbbbbbbb (rolled back; ready: 2 of 2)"
    )
