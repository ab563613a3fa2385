"""The fleet view ends by itself, with code 0, on SIGTERM as on SIGINT, after closing its Zenoh session: systemd
and `kill` send SIGTERM, and a process that dies by the signal skips its last steps and is counted as a crash."""

import signal

import pytest
from fleet_support import running_fleet

pytestmark = pytest.mark.process  # joshua-fleet

END_TIMEOUT_S = 30.0


@pytest.mark.parametrize("stop_signal", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_stop_signal_ends_the_fleet_view_with_code_0(tmp_path, stop_signal):
    with running_fleet(tmp_path) as fleet:
        fleet.process.send_signal(stop_signal)
        code = fleet.process.wait(timeout=END_TIMEOUT_S)
    assert code == 0, f"joshua-fleet ended with {code}:\n{fleet.log.read_text()}"
