"""The QoS verdict table agrees with rclpy.qos.qos_check_compatible; the compiler never imports rclpy."""

import itertools
import subprocess
import sys

import pytest
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSCompatibility,
    QoSProfile,
    ReliabilityPolicy,
    qos_check_compatible,
)

from joshua_codegen.qos_compat import LEVELS, compatible, incompatible_policies

HISTORIES = (("KEEP_LAST", 1), ("KEEP_LAST", 10), ("KEEP_ALL", 0))


def profile(qos: dict) -> QoSProfile:
    return QoSProfile(
        history=HistoryPolicy[qos["history"]],
        depth=qos["depth"],
        reliability=ReliabilityPolicy[qos["reliability"]],
        durability=DurabilityPolicy[qos["durability"]],
        # The policy rmw applies by default; SYSTEM_DEFAULT would only give "WARNING: unknown".
        liveliness=LivelinessPolicy.AUTOMATIC,
    )


def all_profiles():
    for reliability, durability, (history, depth) in itertools.product(
        LEVELS["reliability"], LEVELS["durability"], HISTORIES
    ):
        yield {"reliability": reliability, "durability": durability, "history": history, "depth": depth}


def test_verdicts_match_rclpy_for_every_pair():
    pairs = 0
    for offered, requested in itertools.product(list(all_profiles()), repeat=2):
        verdict, _ = qos_check_compatible(profile(offered), profile(requested))
        assert verdict in (QoSCompatibility.OK, QoSCompatibility.ERROR)
        assert compatible(offered, requested) == (verdict == QoSCompatibility.OK), (offered, requested)
        pairs += 1
    assert pairs == 144


def test_the_failing_policy_is_named():
    best_effort = {"reliability": "BEST_EFFORT", "durability": "VOLATILE"}
    strict = {"reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}
    assert incompatible_policies(best_effort, strict) == ["reliability", "durability"]
    assert incompatible_policies(strict, best_effort) == []


@pytest.mark.process
def test_the_compiler_does_not_import_rclpy():
    code = (
        "import sys\n"
        "import joshua_codegen.check, joshua_codegen.fmt, joshua_codegen.rules\n"
        "joshua_codegen.rules.all_rules()\n"
        "assert not [m for m in sys.modules if m.split('.')[0] in ('rclpy', 'rosidl_runtime_py')], 'ROS imported'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
