"""`joshua-servo` against emulated buses on ptys: scan, ping, set-id, set-baud, status, find-port, errors."""

import json
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import serial

from joshua_runtime.drivers.sts3215_table import BAUD_RATE_CODES
from joshua_runtime.emulators.pty_link import PtyLink
from joshua_runtime.servo_tools import find_port
from joshua_runtime.servo_tools.cli import main

SIX = [1, 2, 3, 4, 5, 6]


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_scan_finds_servos_at_every_baud_rate(emulators, capsys):
    emulator = emulators("ttyMIXED", ids=SIX)
    emulator.write_register(4, "Baud_Rate", BAUD_RATE_CODES[115_200])
    emulator.write_register(6, "Baud_Rate", BAUD_RATE_CODES[500_000])
    code, out, err = run(capsys, "scan", emulator.link, "--json")
    assert (code, err) == (0, "")
    found = json.loads(out)
    assert found == [
        {"id": i, "model": "sts3215", "baud_rate": rate, "firmware": "3.10"}
        for i, rate in [(1, 1_000_000), (2, 1_000_000), (3, 1_000_000), (5, 1_000_000), (6, 500_000), (4, 115_200)]
    ]


@pytest.mark.process
def test_console_script_scans_the_joshua_emulate_bus(tmp_path):
    link = tmp_path / "ttyCLI"
    emulator = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.emulators.cli", "sts3215", "--ids", "3,7", "--link", str(link)],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert "sts3215: servos 3,7" in emulator.stdout.readline()
        console_script = Path(sys.executable).parent / "joshua-servo"
        scan = subprocess.run([console_script, "scan", str(link)], capture_output=True, text=True, check=False)
        assert scan.returncode == 0, scan.stderr
        assert scan.stdout.splitlines() == [
            "id   3  sts3215  1000000 baud  firmware 3.10",
            "id   7  sts3215  1000000 baud  firmware 3.10",
        ]
    finally:
        emulator.terminate()
        emulator.wait(5)


def test_set_id_persists_across_a_power_cycle(emulators, capsys):
    emulator = emulators("ttySETID", ids=[1, 2])
    code, out, _ = run(capsys, "set-id", emulator.link, 1, 9)
    assert code == 0 and out.startswith("id 9: sts3215 (model 777)")
    emulator.servo(9).restart(time.monotonic())
    assert emulator.ids == [2, 9]
    assert emulator.read_register(9, "Lock") == 1
    code, _, err = run(capsys, "set-id", emulator.link, 2, 9)
    assert code == 2 and err == f"joshua-servo: error: {emulator.link}: id 9 is already taken at 1000000 baud\n"


def test_set_baud_moves_the_servo_and_scan_follows(emulators, capsys):
    emulator = emulators("ttySETBAUD", ids=[1, 2])
    code, out, _ = run(capsys, "set-baud", emulator.link, 2, 250000)
    assert code == 0 and out.strip().endswith("250000 baud")
    emulator.servo(2).restart(time.monotonic())
    code, out, _ = run(capsys, "ping", emulator.link, 2)
    assert (code, out) == (0, "id 2: sts3215 (model 777), firmware 3.10, 250000 baud\n")
    code, _, err = run(capsys, "set-baud", emulator.link, 2, 9600)
    assert code == 2 and "STS3215 baud rates are 1000000, 500000" in err


def test_status_reports_telemetry_and_error_bits(emulators, capsys):
    emulator = emulators("ttySTATUS", ids=[1, 2, 3])
    emulator.move_by_hand(2, 1500)
    emulator.set_sensor(3, "Present_Temperature", 75)
    emulator.set_sensor(1, "Present_Voltage", 35)
    code, out, _ = run(capsys, "status", emulator.link, "--json")
    assert code == 0
    rows = {row["id"]: row for row in json.loads(out)}
    assert rows[2]["position"] == 1500 and rows[2]["voltage_v"] == 12.1 and rows[2]["errors"] == []
    assert rows[3]["temperature_c"] == 75 and rows[3]["errors"] == ["overheat"]
    assert rows[1]["voltage_v"] == 3.5 and rows[1]["errors"] == ["input voltage"]
    code, out, _ = run(capsys, "status", emulator.link, "--ids", "3")
    assert out.splitlines()[1].split() == ["3", "2048", "0", "0.0", "12.1", "75", "overheat"]


def test_busy_port_names_the_holder(emulators, capsys):
    emulator = emulators("ttyBUSY", ids=[1])
    holder = serial.Serial(str(emulator.link), 1_000_000, exclusive=True)
    try:
        code, out, err = run(capsys, "scan", emulator.link)
    finally:
        holder.close()
    assert code == 4 and out == ""
    assert err.startswith(f"joshua-servo: error: serial port {emulator.link} is busy: another program has it open: ")
    assert "(pid " in err and err.count("\n") == 1


def test_no_answer_and_missing_port(emulators, tmp_path, capsys):
    emulator = emulators("ttyEMPTY", ids=[1])
    code, _, err = run(capsys, "ping", emulator.link, 5)
    assert (code, err) == (5, f"joshua-servo: error: {emulator.link}: no answer from servo id 5 at any baud rate\n")
    code, _, err = run(capsys, "scan", tmp_path / "ttyNONE")
    assert (code, err) == (3, f"joshua-servo: error: serial port {tmp_path / 'ttyNONE'} not found\n")


def test_two_servos_on_one_id_are_reported(emulators, capsys):
    emulator = emulators("ttyTWINS", ids=[1, 1, 2])
    code, out, err = run(capsys, "scan", emulator.link, "--json")
    assert code == 6
    assert json.loads(out) == [{"id": 2, "model": "sts3215", "baud_rate": 1_000_000, "firmware": "3.10"}]
    assert err == "joshua-servo: error: two servos share id 1 at 1000000 baud (their replies collide)\n"
    code, _, err = run(capsys, "status", emulator.link, "--ids", "1,2")
    assert (code, "garbled replies from servo id 1" in err, "two servos share this id?" in err) == (6, True, True), err


def test_find_port_watches_a_device_appear_and_vanish(tmp_path, capsys):
    pattern = str(tmp_path / "ttyUSB*")
    links = []

    def plug():
        time.sleep(0.3)
        links.append(PtyLink(tmp_path / "ttyUSB0"))

    plugger = threading.Thread(target=plug)
    plugger.start()
    code, out, _ = run(capsys, "find-port", "--watch", 5, "--pattern", pattern)
    plugger.join()  # the device appears before PtyLink returns it: the watch can end first
    assert code == 0 and out.splitlines()[-1] == f"appeared: {tmp_path / 'ttyUSB0'}"
    change = find_port.find_port_interactive(
        lambda: find_port.list_devices([pattern]), lambda prompt: links.pop().close()
    )
    assert change.describe() == f"vanished: {tmp_path / 'ttyUSB0'}"
    code, out, _ = run(capsys, "find-port", "--watch", 0.3, "--pattern", pattern)
    assert code == 1 and out.splitlines()[-1] == "no serial device changed"


def test_bad_usage_is_one_line(emulators, capsys):
    emulator = emulators("ttyUSAGE", ids=[1])
    code, _, err = run(capsys, "set-id", emulator.link, 1, 300)
    assert (code, err) == (2, "joshua-servo: error: servo ids are 0-253, not 300\n")
    with pytest.raises(SystemExit) as exited:
        main(["calibrate", str(emulator.link), "--robot", "koch"])
    assert exited.value.code == 2
    assert "argument --robot: invalid choice: 'koch'" in capsys.readouterr().err
