"""The dashboard ends by itself, with code 0, on SIGTERM as on SIGINT: a process manager sends either (the
supervisor's cascade, `kill`, systemd), and one that dies by the signal is counted as a crash and restarted."""

import os
import re
import signal
import time

import pytest
from dashboard_support import free_port, node_pid, running_robot

pytestmark = pytest.mark.process

ROBOT = """robot_config {{ name: "signalled" mode: MODE_TELEOPERATION
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" }}
  dashboard {{ port: {port} bind: "127.0.0.1" }}
}}
"""
END_TIMEOUT_S = 30.0


def ended(log, pid: int) -> str | None:
    """How the supervisor says process `pid` ended ("exited with code N", "killed by SIGNAL"), once it has."""
    found = re.search(rf"dashboard: pid {pid} (exited with code \d+|killed by \w+)", log.read_text())
    return found.group(1) if found else None


@pytest.mark.parametrize("stop_signal", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_stop_signal_ends_the_dashboard_with_code_0(tmp_path, ros_env, stop_signal):
    port = free_port()
    with running_robot(ROBOT.format(port=port), tmp_path, ros_env, port) as control_socket:
        pid = node_pid(control_socket, "dashboard")
        os.kill(pid, stop_signal)
        deadline = time.monotonic() + END_TIMEOUT_S
        while ended(tmp_path / "supervisor.log", pid) is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert ended(tmp_path / "supervisor.log", pid) == "exited with code 0", (
            tmp_path / "supervisor.log"
        ).read_text()
