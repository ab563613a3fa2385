"""The guided calibration in the panel: one joint at a time, set home, sweep with live MIN/POS/MAX, save."""

from pathlib import Path

from PySide6.QtCore import Signal
from PySide6.QtWidgets import (
    QCheckBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QPushButton,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from joshua_runtime.servo_tools.calibration_flow import ArmModel

COLUMNS = ("joint", "state", "offset", "MIN", "POS", "MAX")


class CalibrationPanel(QWidget):
    """Drives the worker's calibration through `step(name, argument)`; shows its progress."""

    step = Signal(str, object)

    def __init__(self, arm: ArmModel, output: Path, parent=None):
        super().__init__(parent)
        self.arm, self.index = arm, -1
        self.instruction = QLabel("Start, then follow the instructions joint by joint. Torque goes off.")
        self.instruction.setObjectName("instruction")
        self.instruction.setWordWrap(True)
        self.table = QTableWidget(len(arm.joints), len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.verticalHeader().setVisible(False)
        for row, joint in enumerate(arm.joints):
            self.table.setItem(row, 0, QTableWidgetItem(joint))
            self.table.setItem(row, 1, QTableWidgetItem("—"))
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.Stretch)
        self.start_button = QPushButton("Start calibration")
        self.home_button = QPushButton("Set home here")
        self.next_button = QPushButton("Next joint")
        self.output = QLineEdit(str(output))
        self.save_button = QPushButton("Save")
        self.replace = QCheckBox("replace")
        self.start_button.clicked.connect(self.start)
        self.home_button.clicked.connect(self.home)
        self.next_button.clicked.connect(self.next_joint)
        self.save_button.clicked.connect(self.save)
        buttons = QHBoxLayout()
        for button in (self.start_button, self.home_button, self.next_button):
            buttons.addWidget(button)
        buttons.addStretch(1)
        buttons.addWidget(QLabel("file"))
        buttons.addWidget(self.output, 2)
        buttons.addWidget(self.replace)
        buttons.addWidget(self.save_button)
        layout = QVBoxLayout(self)
        layout.addWidget(self.instruction)
        layout.addLayout(buttons)
        layout.addWidget(self.table, 1)
        self._enable(start=True)

    def _enable(self, start=False, home=False, next_=False, save=False) -> None:
        self.start_button.setEnabled(start)
        self.home_button.setEnabled(home)
        self.next_button.setEnabled(next_)
        self.save_button.setEnabled(save)

    @property
    def joint(self) -> str:
        return self.arm.joints[self.index]

    def start(self) -> None:
        self.index = -1
        self.step.emit("start", None)

    def home(self) -> None:
        self.step.emit("home", self.joint)

    def save(self) -> None:
        """Ask the worker to store the calibration; an existing file is kept unless `replace` is ticked."""
        path = Path(self.output.text())
        if path.exists() and not self.replace.isChecked():
            self.instruction.setText(f"{path} exists: tick replace to overwrite it, or choose another file.")
            return
        self.step.emit("finish", path)

    def next_joint(self) -> None:
        self._set(self.index, 1, "done")
        self.index += 1
        if self.index == len(self.arm.joints):
            self.instruction.setText("Every joint is calibrated. Save writes the LeRobot calibration file.")
            self._enable(save=True)
            return
        self._set(self.index, 1, "homing")
        self.instruction.setText(f"{self.arm.homing_instruction(self.joint)} Then press Set home here.")
        self._enable(home=True)

    def progress(self, event) -> None:
        """Events from the worker: (kind, joint, payload)."""
        kind, joint, payload = event
        if kind == "started":
            self.next_joint()
        elif kind == "homed":
            row = self.arm.joints.index(joint)
            offset, reading = payload
            self._set(row, 1, "sweeping" if joint not in self.arm.continuous_joints else "full turn")
            self._set(row, 2, str(offset))
            self._show_range(row, reading)
            self.instruction.setText(f"{self.arm.sweep_instruction(joint)} Then press Next joint.")
            self._enable(next_=True)
        elif kind == "range":
            self._show_range(self.arm.joints.index(joint), payload)
        elif kind == "saved":
            self.instruction.setText(f"Calibration written to {joint}.")
            for row, name in enumerate(self.arm.joints):
                self._set(row, 2, str(payload[name].homing_offset))
            self._enable(start=True)

    def _show_range(self, row: int, reading) -> None:
        for column, value in zip((3, 4, 5), (reading.low, reading.position, reading.high)):
            self._set(row, column, str(value))

    def _set(self, row: int, column: int, text: str) -> None:
        if 0 <= row < self.table.rowCount():
            self.table.setItem(row, column, QTableWidgetItem(text))
