"""The Pybricks driver against the emulated hub over a Bumble link (real HCI, L2CAP, ATT and GATT)."""

import os
import socket
import subprocess
import sys
import time

import pytest

from joshua_core.device_link import DEVICE_SILENCE_S
from joshua_runtime.drivers.pybricks import PybricksHub
from joshua_runtime.drivers.pybricks_bumble import BumbleTransport
from joshua_runtime.emulators.pybricks import HubFaults
from joshua_runtime.errors import DeviceError


def wait_for(condition, timeout=3.0):
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.01)


def test_the_driver_downloads_starts_and_drives_the_program(linked_hub, blob):
    driver, emulated = linked_hub()
    assert emulated.program == blob and emulated.running
    assert driver.set_speeds(360, -180).result(2) is not None
    time.sleep(1.0)
    # ramped at 2000 deg/s^2 then steady: about 360 deg/s over ~1 s
    assert 250 < driver.latest.left_deg < 420
    assert -210 < driver.latest.right_deg < -125
    assert driver.stop_wheels().result(2) is not None
    wait_for(lambda: emulated.left.speed_dps == 0)


def test_garbage_on_stdout_costs_lines_not_values(linked_hub):
    driver, emulated = linked_hub(HubFaults(garbage_rate=0.5, seed=3))
    for _ in range(20):
        assert driver.set_speeds(90, 90).result(2) is not None
    time.sleep(0.3)
    assert driver.lines.rejected > 0
    assert abs(driver.latest.left_deg - emulated.left.angle_deg) < 30
    assert emulated.reports[0].startswith("fault: garbage before 1 of ")
    assert emulated.reports[0].endswith(" stdout lines so far (--garbage-rate)")


def test_a_hub_that_never_starts_the_program_is_a_clear_error(linked_hub):
    driver, emulated = linked_hub(HubFaults(never_start=True), open=False)
    with pytest.raises(DeviceError, match="did not start its program"):
        driver.open()
    assert emulated.reports == ["fault: program accepted, never started (--never-start)"]


def test_the_link_lost_mid_command_is_reconnected(linked_hub):
    driver, emulated = linked_hub(HubFaults(drop_link_after=3))
    assert driver.set_speeds(100, 100).result(2) is not None
    assert driver.set_speeds(100, 100).result(2) is not None
    assert driver.set_speeds(100, 100).result(2) is None  # the link drops on this one
    assert emulated.reports == ["fault: dropping the link on stdin command 3 (--drop-link-after)"]
    wait_for(lambda: driver.reconnects == 1 and driver.connected, timeout=5.0)
    assert emulated.running  # the program went on running: not downloaded again
    # Acknowledged again (a command whose acknowledgement misses the driver's 1 s on a busy machine is None).
    wait_for(lambda: driver.set_speeds(50, 50).result(2) is not None, timeout=10.0)


def test_a_hub_that_goes_silent_is_declared_lost_and_its_program_started_again(linked_hub):
    driver, emulated = linked_hub()
    emulated.running = False  # the program ends without a word: no more angle reports, the link still up
    wait_for(lambda: driver.link_lost_at is not None, timeout=DEVICE_SILENCE_S + 2.0)
    assert driver.lost_reason == f"no wheel angles for {DEVICE_SILENCE_S:g} s"
    assert driver.set_speeds(50, 50).result(2) is None  # dropped while the link is down
    wait_for(lambda: driver.reconnects == 1 and driver.connected, timeout=5.0)
    assert driver.link_lost_at is None and driver.link_losses == 1
    assert emulated.running  # started again on the reconnection
    # Acknowledged again (a command whose acknowledgement misses the driver's 1 s on a busy machine is None).
    wait_for(lambda: driver.set_speeds(50, 50).result(2) is not None, timeout=10.0)


def test_an_absent_hub_is_a_clear_error(blob):
    driver = PybricksHub("No Such Hub", BumbleTransport(hci="tcp-client:127.0.0.1:1"), blob)
    with pytest.raises(DeviceError, match="cannot open Bluetooth controller"):
        driver.open()
    driver.close()


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


@pytest.mark.process
def test_joshua_emulate_serves_the_hub_to_another_process(blob):
    port = free_port()
    emulator = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.emulators.cli", "pybricks", "--port", str(port)],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    try:
        assert "reachable over hci tcp-client:127.0.0.1:" in emulator.stdout.readline()
        driver = PybricksHub("F4:B8:5E:00:00:01", BumbleTransport(hci=f"tcp-client:127.0.0.1:{port}"), blob)
        driver.open()
        try:
            assert driver.set_speeds(200, 200).result(2) is not None
            wait_for(lambda: driver.latest.left_deg > 50)
        finally:
            driver.close()
    finally:
        emulator.terminate()
        assert emulator.wait(5) == 0


def test_without_bluez_bleak_fails_in_one_clear_line(blob):
    from joshua_runtime.drivers.pybricks_transport import BleakTransport

    driver = PybricksHub("Pybricks Hub", BleakTransport(), blob)
    try:
        with pytest.raises(DeviceError, match="BlueZ|cannot connect|no Pybricks hub"):
            driver.open()
    finally:
        driver.close()
