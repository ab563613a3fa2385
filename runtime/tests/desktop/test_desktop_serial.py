"""The panel on an emulated bus: sliders, torque, presets, e-stop, live plots, health and calibration."""

import json
import math

from desktop_helpers import IDS, JOINTS, LINK_TIMEOUT_MS, close_panel, open_panel
from PySide6.QtCore import Qt

from joshua_runtime.desktop.model import BUILTIN_PRESETS
from joshua_runtime.desktop.serial_worker import SerialWorker
from joshua_runtime.drivers.calibration import uncalibrated

WAIT_MS = 10_000  # generous: the machine may be busy; a pass returns at once


def serial_panel(qtbot, emulator, **options):
    worker = SerialWorker(str(emulator.link), JOINTS, IDS, 1_000_000)
    return open_panel(qtbot, worker, **options)


def test_sliders_torque_presets_and_estop_drive_the_bus(qtbot, emulators, screenshot):
    emulator = emulators("ttyPANEL", ids=[*IDS, 7])  # id 7 is on the bus but not in the arm
    emulator.write_register(7, "Torque_Enable", 1)
    window = serial_panel(qtbot, emulator)
    try:
        assert window.link.text().startswith(f"serial {emulator.link} @ 1000000 baud, 6 servos")
        torque_on = next(b for b in window.findChildren(type(window.estop)) if b.text() == "Torque on")
        qtbot.mouseClick(torque_on, Qt.MouseButton.LeftButton)
        qtbot.waitUntil(lambda: all(emulator.read_register(i, "Torque_Enable") == 1 for i in IDS), timeout=WAIT_MS)

        qtbot.waitUntil(lambda: window.joint_panel.rows["shoulder_pan"].torque.isChecked(), timeout=WAIT_MS)
        window.joint_panel.rows["shoulder_pan"].slider.setValue(300)  # 30.0 degrees
        goal = uncalibrated(1).to_ticks(math.radians(30.0))
        qtbot.waitUntil(lambda: emulator.read_register(1, "Goal_Position") == goal, timeout=WAIT_MS)
        qtbot.waitUntil(lambda: emulator.position(1) == goal, timeout=WAIT_MS)

        qtbot.mouseClick(window.findChild(type(window.estop), "preset_grip_open"), Qt.MouseButton.LeftButton)
        grip = uncalibrated(6).to_ticks(BUILTIN_PRESETS["grip_open"]["gripper"])
        qtbot.waitUntil(lambda: emulator.read_register(6, "Goal_Position") == grip, timeout=WAIT_MS)
        assert emulator.read_register(1, "Goal_Position") == goal  # a preset leaves other joints alone

        window.joint_panel.rows["wrist_flex"].torque.click()  # text-less box: click() hits the indicator
        qtbot.waitUntil(lambda: emulator.read_register(4, "Torque_Enable") == 0, timeout=WAIT_MS)
        assert emulator.read_register(3, "Torque_Enable") == 1

        qtbot.waitUntil(lambda: all(len(chart.times) > 10 for chart in window.charts[:2]), timeout=WAIT_MS)
        screenshot(window, "serial_panel")
        qtbot.mouseClick(window.estop, Qt.MouseButton.LeftButton)
        qtbot.waitUntil(
            lambda: all(emulator.read_register(i, "Torque_Enable") == 0 for i in [*IDS, 7]), timeout=WAIT_MS
        )
        qtbot.waitUntil(lambda: "E-STOP" in window.statusBar().currentMessage(), timeout=WAIT_MS)
    finally:
        close_panel(window)


def test_plots_and_health_show_temperature_voltage_and_faults(qtbot, emulators, screenshot):
    emulator = emulators("ttyHEALTH")
    emulator.set_sensor(3, "Present_Temperature", 75)
    emulator.set_sensor(5, "Present_Voltage", 42)
    window = serial_panel(qtbot, emulator)
    try:
        temperature, voltage = window.charts[2], window.charts[3]
        qtbot.waitUntil(lambda: len(temperature.times) > 5, timeout=WAIT_MS)
        assert temperature.latest("elbow_flex") == 75 and voltage.latest("wrist_roll") == 4.2
        assert voltage.latest("shoulder_pan") == 12.1
        health = window.health.texts
        qtbot.waitUntil(lambda: "overheat" in health["elbow_flex"].text(), timeout=WAIT_MS)
        assert health["elbow_flex"].text() == "servo reports overheat; temperature 75 C at or above 70 C"
        assert health["wrist_roll"].text() == "voltage 4.2 V near its limit"
        assert health["gripper"].text() == "OK"
        qtbot.waitUntil(lambda: temperature.frames_painted > 3, timeout=WAIT_MS)
        screenshot(window, "health")
    finally:
        close_panel(window)


def test_calibration_tab_writes_a_lerobot_file(qtbot, emulators, tmp_path, screenshot):
    emulator = emulators("ttyCALIBRATE")
    output = tmp_path / "follower.json"
    window = serial_panel(qtbot, emulator, calibration_output=output)
    panel = window.calibration
    mounts = dict(zip(JOINTS, (300, 3700, 1500, 60, 2900, 1000)))
    stops = (-900, 1000)
    try:
        window.tabs.setCurrentWidget(panel)
        qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
        for joint, servo_id in zip(JOINTS, IDS):
            qtbot.waitUntil(panel.home_button.isEnabled, timeout=WAIT_MS)
            assert panel.instruction.text().startswith(f"Hold {joint} at its homing pose")
            emulator.turn_shaft(servo_id, mounts[joint])
            qtbot.mouseClick(panel.home_button, Qt.MouseButton.LeftButton)
            qtbot.waitUntil(panel.next_button.isEnabled, timeout=WAIT_MS)
            if joint != "wrist_roll":
                for ticks in stops:
                    emulator.turn_shaft(servo_id, (mounts[joint] + ticks) % 4096)
                    row = JOINTS.index(joint)
                    qtbot.waitUntil(
                        lambda r=row, t=ticks: panel.table.item(r, 4).text() == str(2047 + t), timeout=WAIT_MS
                    )
            if joint == "elbow_flex":
                screenshot(window, "calibration")
            qtbot.mouseClick(panel.next_button, Qt.MouseButton.LeftButton)
        qtbot.waitUntil(panel.save_button.isEnabled, timeout=WAIT_MS)
        output.write_text("{}")  # an earlier calibration is never replaced by surprise
        qtbot.mouseClick(panel.save_button, Qt.MouseButton.LeftButton)
        assert panel.instruction.text().startswith(f"{output} exists: tick replace")
        assert output.read_text() == "{}"
        panel.replace.setChecked(True)
        qtbot.mouseClick(panel.save_button, Qt.MouseButton.LeftButton)
        qtbot.waitUntil(lambda: output.read_text() != "{}", timeout=LINK_TIMEOUT_MS)
        saved = json.loads(output.read_text())
        assert saved["elbow_flex"] == {
            "id": 3,
            "drive_mode": 0,
            "homing_offset": 1500 - 2047,
            "range_min": 2047 - 900,
            "range_max": 2047 + 1000,
        }
        assert (saved["wrist_roll"]["range_min"], saved["wrist_roll"]["range_max"]) == (0, 4095)
        qtbot.waitUntil(lambda: panel.instruction.text() == f"Calibration written to {output}.", timeout=WAIT_MS)
    finally:
        close_panel(window)
