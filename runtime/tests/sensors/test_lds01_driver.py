"""LDS-01 driver against the emulator and hand-made byte streams over pseudo-terminals."""

import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from joshua_runtime.drivers import lds01_protocol as proto
from joshua_runtime.drivers.lds01 import Lds01Driver
from joshua_runtime.emulators.lds01 import Lds01Emulator
from joshua_runtime.emulators.pty_link import PtyLink
from joshua_runtime.errors import DeviceError

EMULATOR_START_TIMEOUT_S = 10.0
EMULATOR_EXIT_TIMEOUT_S = 5.0

# Known angles of the synthetic room (see drivers/synthetic_room.py), in metres.
KNOWN_RANGES = {0: 0.8, 45: 2.121, 90: 1.5, 180: 0.0, 270: 1.0}


def f32(value: float) -> float:
    """A float as it survives a protobuf float field."""
    return float(np.float32(value))


def readings_of_packet(k: int) -> list[int]:
    return [proto.scan_index(k, j) for j in range(proto.READINGS_PER_PACKET)]


def test_full_turn_from_the_emulator_has_exact_ranges_at_known_angles(tmp_path):
    port = str(tmp_path / "ttyLDS")
    with Lds01Emulator(port) as emulator, Lds01Driver(port, frame_id="lidar") as lidar:
        scans = [lidar.read_scan() for _ in range(2)]
        assert emulator.stream.spinning
    for scan in scans:
        sensor = scan.sensor
        assert scan.frame_id == "lidar"
        assert sensor.kind == "laser_scan"
        assert len(sensor.ranges) == 360 and len(sensor.intensities) == 360
        for angle, metres in KNOWN_RANGES.items():
            assert sensor.ranges[angle] == f32(metres), angle
        assert sensor.intensities[0] == 4000 - 800
        assert sensor.intensities[180] == 0
        assert sensor.angle_min == 0.0
        assert sensor.angle_increment == f32(2 * math.pi / 360)
        assert sensor.angle_max == f32(2 * math.pi - 2 * math.pi / 360)
        assert (sensor.range_min, sensor.range_max) == (f32(0.12), f32(3.5))
        assert sensor.time_increment == f32(1 / 1800)
        assert sensor.scan_time == f32(0.2)
        assert list(sensor.values) == [300.0]
    assert lidar.packets_good == 120 and lidar.packets_skipped == 0


def _counting_turn(speed: int = 3000) -> bytes:
    """A turn whose reading n = 6k + j has range 1000 + n mm and intensity n."""
    return b"".join(
        proto.encode_packet(k, speed, [(6 * k + j, 1000 + 6 * k + j) for j in range(6)])
        for k in range(proto.PACKETS_PER_TURN)
    )


def test_reading_n_goes_to_index_359_minus_n_after_resync_on_fa_a0(tmp_path):
    turn = _counting_turn()
    # Garbage, a lone 0xFA, then a sync split across two writes.
    with PtyLink(tmp_path / "ttyRAW") as link, Lds01Driver(str(tmp_path / "ttyRAW")) as lidar:
        os.write(link.master_fd, b"\x00\x13\xfa\x07" + turn[:1])
        time.sleep(0.1)
        os.write(link.master_fd, turn[1:])
        scan = lidar.read_scan()
    for n in range(360):
        assert scan.sensor.ranges[359 - n] == f32((1000 + n) / 1000.0)
        assert scan.sensor.intensities[359 - n] == n


def test_corrupt_packets_are_skipped_and_their_readings_stay_zero(tmp_path):
    corrupt = {3, 10, 59}
    with Lds01Emulator(tmp_path / "ttyLDS", corrupt_packets=corrupt), Lds01Driver(str(tmp_path / "ttyLDS")) as lidar:
        scan = lidar.read_scan()
    clean = _clean_ranges()
    zeroed = {index for k in corrupt for index in readings_of_packet(k)}
    for index in range(360):
        expected = 0.0 if index in zeroed else clean[index]
        assert scan.sensor.ranges[index] == f32(expected), index
    assert (lidar.packets_good, lidar.packets_skipped) == (57, 3)


def test_random_corruption_never_leaks_a_wrong_reading(tmp_path):
    clean = _clean_ranges()
    turns = 3
    with Lds01Emulator(tmp_path / "ttyLDS", corrupt_rate=0.2, seed=3), Lds01Driver(str(tmp_path / "ttyLDS")) as lidar:
        scans = [lidar.read_scan() for _ in range(turns)]
    for scan in scans:
        for index, value in enumerate(scan.sensor.ranges):
            assert value in (0.0, f32(clean[index])), index
    assert lidar.packets_skipped > 0
    assert lidar.packets_good + lidar.packets_skipped == 60 * (turns + lidar.turns_dropped)


def test_checksum_check_is_opt_in(tmp_path):
    turn = bytearray(_counting_turn())
    turn[7 * 42 + 6] ^= 0x01  # flip a range bit of packet 7, checksum unchanged
    for verify, expected_good in ((False, 60), (True, 59)):
        port = str(tmp_path / "ttyRAW")
        with PtyLink(port) as link, Lds01Driver(port, verify_checksum=verify) as lidar:
            os.write(link.master_fd, bytes(turn))
            scan = lidar.read_scan()
        assert lidar.packets_good == expected_good
        assert (scan.sensor.ranges[proto.scan_index(7, 0)] == 0.0) == verify


def test_emulator_packets_pass_the_checksum(tmp_path):
    with Lds01Emulator(tmp_path / "ttyLDS"), Lds01Driver(str(tmp_path / "ttyLDS"), verify_checksum=True) as lidar:
        lidar.read_scan()
    assert (lidar.packets_good, lidar.packets_skipped) == (60, 0)


def test_motor_starts_on_open_and_stops_on_close(tmp_path):
    with Lds01Emulator(tmp_path / "ttyLDS") as emulator:
        time.sleep(0.1)
        assert emulator.stream.packets_sent == 0 and not emulator.stream.spinning
        with Lds01Driver(str(tmp_path / "ttyLDS")) as lidar:
            lidar.read_scan()
        time.sleep(0.1)
        assert not emulator.stream.spinning
        sent = emulator.stream.packets_sent
        time.sleep(0.1)
        assert emulator.stream.packets_sent == sent


def test_missing_port_is_a_clear_device_error(tmp_path):
    port = tmp_path / "ttyNOPE"
    with pytest.raises(DeviceError, match=rf"^cannot open LDS-01 lidar at {port}: .*No such file") as info:
        Lds01Driver(str(port)).open()
    assert "\n" not in str(info.value)
    assert info.value.exit_code == 3


def test_silent_device_times_out_with_a_named_timeout(tmp_path):
    with PtyLink(tmp_path / "ttySILENT"):
        lidar = Lds01Driver(str(tmp_path / "ttySILENT"), silent_timeout_s=0.3)
        with lidar, pytest.raises(DeviceError, match=r"sent no usable scan within 0.3 s"):
            lidar.read_scan()


def test_read_scan_returns_none_when_asked_to_stop(tmp_path):
    with PtyLink(tmp_path / "ttySILENT"), Lds01Driver(str(tmp_path / "ttySILENT")) as lidar:
        started = time.monotonic()
        assert lidar.read_scan(should_stop=lambda: time.monotonic() - started > 0.1) is None


@pytest.mark.process
def test_joshua_emulate_lds01_serves_until_sigint(tmp_path):
    link = tmp_path / "ttyCLI"
    process = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.emulators.cli", "lds01", "--link", str(link), "--corrupt-rate", "0"],
    )
    try:
        deadline = time.monotonic() + EMULATOR_START_TIMEOUT_S
        while not link.is_symlink() and time.monotonic() < deadline:
            time.sleep(0.02)
        with Lds01Driver(str(link)) as lidar:
            scan = lidar.read_scan()
        assert scan.sensor.ranges[90] == f32(1.5)
    finally:
        process.send_signal(signal.SIGINT)
        assert process.wait(EMULATOR_EXIT_TIMEOUT_S) == 0
    assert not link.is_symlink()


def _clean_ranges() -> list[float]:
    from joshua_runtime.drivers import synthetic_room

    return [mm / 1000.0 for mm in synthetic_room.scan_mm()]
