"""One line per joint: a coloured level dot and what is wrong, from the STS3215 limits."""

from PySide6.QtWidgets import QGridLayout, QLabel, QWidget

from joshua_runtime.desktop.model import JointSample

LEVEL_COLORS = {0: "#57ab5a", 1: "#c69026", 2: "#e5534b"}
LEVEL_NAMES = {0: "OK", 1: "WARN", 2: "ERROR"}
UNKNOWN_COLOR = "#545d68"


class HealthPanel(QWidget):
    def __init__(self, joints: list[str], parent=None):
        super().__init__(parent)
        grid = QGridLayout(self)
        grid.setVerticalSpacing(3)
        self.dots, self.texts = {}, {}
        for row, name in enumerate(joints):
            self.dots[name], self.texts[name] = QLabel("●"), QLabel("no reading yet")
            self.texts[name].setObjectName(f"health_{name}")
            grid.addWidget(self.dots[name], row, 0)
            grid.addWidget(QLabel(name), row, 1)
            grid.addWidget(self.texts[name], row, 2)
        grid.setColumnStretch(2, 1)

    def show(self, samples: dict[str, JointSample]) -> None:
        for name, sample in samples.items():
            if name not in self.dots:
                continue
            if sample.health is None:
                color, text = UNKNOWN_COLOR, "not reported over this link"
            else:
                color = LEVEL_COLORS[sample.health]
                text = "; ".join(sample.findings) or LEVEL_NAMES[sample.health]
            style = f"color: {color};"
            if self.dots[name].styleSheet() != style:  # restyling is costly: only on a change
                self.dots[name].setStyleSheet(style)
            if self.texts[name].text() != text:
                self.texts[name].setText(text)
