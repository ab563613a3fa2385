"""The panel's window: link and e-stop on top, joints and presets on the left, plots and calibration right."""

import math
import time
from pathlib import Path

from PySide6.QtCore import QTimer, Signal
from PySide6.QtWidgets import (
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QMainWindow,
    QPushButton,
    QSizePolicy,
    QTabWidget,
    QVBoxLayout,
    QWidget,
)

from joshua_runtime.desktop.calibration_panel import CalibrationPanel
from joshua_runtime.desktop.health_panel import HealthPanel
from joshua_runtime.desktop.joint_panel import JointPanel
from joshua_runtime.desktop.model import JointLimits, Presets, Telemetry
from joshua_runtime.desktop.plot import StripChart
from joshua_runtime.desktop.style import STYLESHEET, joint_colors
from joshua_runtime.desktop.worker import LinkThread, LinkWorker
from joshua_runtime.servo_tools.calibration_flow import ArmModel

FRAME_HZ = 30.0
RATE_WINDOW_S = 1.0
# (title, unit, value of a JointSample, smallest span of the y axis)
CHARTS = (
    ("Position", "deg", lambda s: math.degrees(s.position), 10.0),
    ("Load", "%", lambda s: s.load_percent, 10.0),
    ("Temperature", "°C", lambda s: s.temperature_c, 5.0),
    ("Voltage", "V", lambda s: s.voltage_v, 1.0),
)


class MainWindow(QMainWindow):
    goals_requested = Signal(object)
    torque_requested = Signal(bool)
    joint_torque_requested = Signal(str, bool)
    estop_requested = Signal()

    def __init__(
        self,
        worker: LinkWorker,
        joints: list[str],
        limits: dict[str, JointLimits],
        presets: Presets,
        arm: ArmModel,
        calibration_output: Path,
    ):
        super().__init__()
        self.setWindowTitle("joshua-desktop")
        self.setStyleSheet(STYLESHEET)
        self.joints, self.presets = joints, presets
        self.link_failed = False
        colors = joint_colors(joints)
        self.link = QLabel("connecting…")
        self.link.setObjectName("link")
        self.link.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)  # long paths clip
        self.rates = QLabel("")
        self.rates.setObjectName("rates")
        self.estop = QPushButton("E-STOP")
        self.estop.setObjectName("estop")
        torque_on, torque_off = QPushButton("Torque on"), QPushButton("Torque off")
        top = QHBoxLayout()
        top.addWidget(self.link, 1)
        top.addSpacing(16)
        top.addWidget(self.rates)
        top.addSpacing(16)
        top.addWidget(torque_on)
        top.addWidget(torque_off)
        top.addSpacing(12)
        top.addWidget(self.estop)

        self.joint_panel = JointPanel(joints, colors, limits)
        joints_box = QGroupBox("Joints")
        QVBoxLayout(joints_box).addWidget(self.joint_panel)
        presets_box = QGroupBox("Presets")
        preset_row = QHBoxLayout(presets_box)
        for name in presets.names():
            button = QPushButton(name)
            button.setObjectName(f"preset_{name}")
            button.clicked.connect(lambda _=False, n=name: self.apply_preset(n))
            preset_row.addWidget(button)
        preset_row.addStretch(1)
        self.health = HealthPanel(joints)
        health_box = QGroupBox("Servo health")
        QVBoxLayout(health_box).addWidget(self.health)
        left = QVBoxLayout()
        left.addWidget(joints_box)
        left.addWidget(presets_box)
        left.addWidget(health_box)
        left.addStretch(1)

        self.charts = [StripChart(title, unit, colors, span) for title, unit, _, span in CHARTS]
        plots = QWidget()
        grid = QGridLayout(plots)
        grid.setSpacing(6)
        for index, chart in enumerate(self.charts):
            grid.addWidget(chart, index // 2, index % 2)
        self.calibration = CalibrationPanel(arm, calibration_output)
        self.tabs = QTabWidget()
        self.tabs.addTab(plots, "Telemetry")
        self.tabs.addTab(self.calibration, "Calibration")

        body = QHBoxLayout()
        body.addLayout(left, 5)
        body.addWidget(self.tabs, 6)
        central = QWidget()
        layout = QVBoxLayout(central)
        layout.addLayout(top)
        layout.addLayout(body, 1)
        self.setCentralWidget(central)
        self.resize(1480, 760)

        if not worker.direct_bus:
            for chart in self.charts[2:]:
                chart.empty_text = "not reported over this link"
            self.joint_panel.set_per_joint_torque(False)
            self.tabs.setTabEnabled(self.tabs.indexOf(self.calibration), False)
            self.tabs.setTabToolTip(self.tabs.indexOf(self.calibration), "needs a direct serial connection")
        self.worker = worker
        self.thread = LinkThread(worker)
        worker.telemetry.connect(self.on_telemetry)
        worker.connected.connect(self.link.setText)
        worker.failed.connect(self.on_failure)
        worker.message.connect(self.on_message)
        worker.calibration.connect(self.calibration.progress)
        self.goals_requested.connect(worker.send_goals)
        self.joint_panel.goals_changed.connect(worker.send_goals)
        self.torque_requested.connect(worker.set_torque)
        self.joint_panel.torque_toggled.connect(worker.set_joint_torque)
        self.estop_requested.connect(worker.estop)
        self.calibration.step.connect(worker.calibrate)
        torque_on.clicked.connect(lambda: self.torque_requested.emit(True))
        torque_off.clicked.connect(lambda: self.torque_requested.emit(False))
        self.estop.clicked.connect(self.estop_requested.emit)

        self.latest: Telemetry | None = None
        self.arrivals: list[float] = []
        self.frames: list[float] = []
        self.frame_timer = QTimer(self)
        self.frame_timer.setInterval(round(1000 / FRAME_HZ))
        self.frame_timer.timeout.connect(self.frame)

    def start(self) -> None:
        self.thread.start()
        self.frame_timer.start()

    def closeEvent(self, event) -> None:
        self.frame_timer.stop()
        self.thread.stop()
        super().closeEvent(event)

    def apply_preset(self, name: str) -> None:
        goals = dict(zip(self.joints, self.presets.goals(name, self.joints)))
        self.joint_panel.apply_goals(goals)
        self.goals_requested.emit(goals)
        self.statusBar().showMessage(f"preset {name}", 3000)

    def on_message(self, text: str) -> None:
        self.statusBar().showMessage(text, 5000)

    def on_failure(self, text: str) -> None:
        self.link_failed = self.latest is None
        if self.link_failed:
            self.link.setText("not connected")
        self.statusBar().showMessage(f"error: {text}")

    def on_telemetry(self, telemetry: Telemetry) -> None:
        self.latest = telemetry
        self.arrivals.append(telemetry.time_s)
        for chart, (_, _, value, _) in zip(self.charts, CHARTS):
            chart.append(telemetry.time_s, {name: value(sample) for name, sample in telemetry.joints.items()})

    def frame(self) -> None:
        """Once per frame: send gathered goals, refresh the numbers and repaint the plots."""
        self.joint_panel.flush()
        now = time.monotonic()
        self.frames = [t for t in self.frames if t > now - RATE_WINDOW_S] + [now]
        self.arrivals = [t for t in self.arrivals if t > now - RATE_WINDOW_S]
        self.rates.setText(f"telemetry {len(self.arrivals) / RATE_WINDOW_S:4.0f} Hz   frames {len(self.frames):3d} fps")
        if self.latest is not None:
            self.joint_panel.show(self.latest.joints)
            self.health.show(self.latest.joints)
        for chart in self.charts:
            chart.update()
