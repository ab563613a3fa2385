"""Per-joint rows: colour, name, goal slider, present angle, load bar, temperature, voltage, torque."""

import math

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import (
    QCheckBox,
    QGridLayout,
    QLabel,
    QProgressBar,
    QSlider,
    QWidget,
)

from joshua_runtime.desktop.model import JointLimits, JointSample

SLIDER_STEPS_PER_DEGREE = 10
LOAD_WARN_PERCENT = 80
FAULT_STYLE = "color: #e5534b;"
HEADERS = ("", "joint", "goal", "", "present", "load", "temp", "volts", "torque")


def _degrees_text(radians: float | None) -> str:
    return "—" if radians is None or math.isnan(radians) else f"{math.degrees(radians):+7.1f}°"


class JointRow:
    """The widgets of one joint, placed on row `row` of a grid."""

    def __init__(self, grid: QGridLayout, row: int, name: str, color: QColor, limits: JointLimits, panel):
        self.name, self.panel = name, panel
        swatch = QLabel()
        swatch.setFixedSize(10, 22)
        swatch.setStyleSheet(f"background: {color.name()}; border-radius: 3px;")
        self.slider = QSlider(Qt.Orientation.Horizontal)
        self.slider.setObjectName(f"slider_{name}")
        self.slider.setRange(
            round(math.degrees(limits.low) * SLIDER_STEPS_PER_DEGREE),
            round(math.degrees(limits.high) * SLIDER_STEPS_PER_DEGREE),
        )
        self.slider.setMinimumWidth(180)
        self.slider.sliderMoved.connect(self._moved)
        self.slider.valueChanged.connect(self._changed)
        self.goal = QLabel("—")
        self.present = QLabel("—")
        self.load = QProgressBar()
        self.load.setRange(0, 100)
        self.load.setTextVisible(True)
        self.load.setFormat("%v %")
        self.load.setFixedWidth(90)
        self.temperature = QLabel("—")
        self.voltage = QLabel("—")
        self.torque = QCheckBox()
        self.torque.setObjectName(f"torque_{name}")
        self.torque.clicked.connect(lambda on: panel.torque_toggled.emit(name, on))
        title = QLabel(name)
        title.setObjectName("jointName")
        for column, widget in enumerate(
            (
                swatch,
                title,
                self.slider,
                self.goal,
                self.present,
                self.load,
                self.temperature,
                self.voltage,
                self.torque,
            )
        ):
            grid.addWidget(widget, row, column)
        for label in (self.goal, self.present, self.temperature, self.voltage):
            label.setObjectName("value")
        self._following = True

    def radians(self) -> float:
        return math.radians(self.slider.value() / SLIDER_STEPS_PER_DEGREE)

    def set_goal(self, radians: float) -> None:
        """Move the slider as a command would (a preset), without echoing it back as a new goal."""
        self.slider.blockSignals(True)
        self.slider.setValue(round(math.degrees(radians) * SLIDER_STEPS_PER_DEGREE))
        self.slider.blockSignals(False)
        self.goal.setText(_degrees_text(self.radians()))

    def _moved(self, _value: int) -> None:
        self._following = False
        self.goal.setText(_degrees_text(self.radians()))
        self.panel.goal_changed(self.name, self.radians())

    def _changed(self, _value: int) -> None:
        if not self.slider.isSliderDown():  # keyboard or wheel: a goal too
            self._moved(_value)

    def show(self, sample: JointSample) -> None:
        self.present.setText(_degrees_text(sample.position))
        load = min(100, round(abs(sample.load_percent)))
        if self.load.value() != load:  # a progress bar repaints on every setValue
            self.load.setValue(load)
        warn = abs(sample.load_percent) >= LOAD_WARN_PERCENT
        if self.load.property("warn") != warn:
            self.load.setProperty("warn", warn)
            self.load.style().polish(self.load)
        self.temperature.setText("—" if sample.temperature_c is None else f"{sample.temperature_c:.0f} °C")
        self.voltage.setText("—" if sample.voltage_v is None else f"{sample.voltage_v:.1f} V")
        if sample.torque_on is not None:
            self.torque.setChecked(sample.torque_on)
        style = FAULT_STYLE if sample.errors else ""
        if self.present.styleSheet() != style:  # restyling is costly: only on a change
            self.present.setStyleSheet(style)
        if sample.torque_on is False or self._following:  # a limp joint's goal is where it is
            self.set_goal(sample.position)
            self._following = sample.torque_on is not True


class JointPanel(QWidget):
    """All joints; emits goals as the user drags and torque changes per joint."""

    goals_changed = Signal(object)  # {joint: rad}
    torque_toggled = Signal(str, bool)

    def __init__(self, joints: list[str], colors: dict[str, QColor], limits: dict[str, JointLimits], parent=None):
        super().__init__(parent)
        grid = QGridLayout(self)
        grid.setHorizontalSpacing(10)
        grid.setVerticalSpacing(6)
        for column, text in enumerate(HEADERS):
            header = QLabel(text)
            header.setObjectName("header")
            grid.addWidget(header, 0, column)
        grid.setColumnStretch(2, 1)
        self.rows = {
            name: JointRow(grid, row + 1, name, colors[name], limits[name], self) for row, name in enumerate(joints)
        }
        self._pending: dict[str, float] = {}

    def goal_changed(self, joint: str, radians: float) -> None:
        self._pending[joint] = radians

    def flush(self) -> None:
        """Send the goals gathered since the last frame in one message."""
        if self._pending:
            self.goals_changed.emit(dict(self._pending))
            self._pending.clear()

    def apply_goals(self, goals: dict[str, float]) -> None:
        for name, value in goals.items():
            if name in self.rows and not math.isnan(value):
                self.rows[name].set_goal(value)
                self.rows[name]._following = False

    def show(self, samples: dict[str, JointSample]) -> None:
        for name, sample in samples.items():
            if name in self.rows:
                self.rows[name].show(sample)

    def set_per_joint_torque(self, available: bool) -> None:
        for row in self.rows.values():
            row.torque.setEnabled(available)
