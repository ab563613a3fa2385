"""The panel's look: a dark theme that keeps numbers legible, and one colour per joint."""

from PySide6.QtGui import QColor

JOINT_COLORS = ("#4cc9f0", "#f72585", "#b5e48c", "#ffb703", "#9d4edd", "#fb8500", "#2ec4b6", "#e63946")

STYLESHEET = """
QWidget { background: #22272e; color: #cdd9e5; font-size: 10pt; }
QGroupBox { border: 1px solid #373e47; border-radius: 6px; margin-top: 14px; padding: 8px; }
QGroupBox::title { subcontrol-origin: margin; left: 10px; padding: 0 4px; color: #768390; }
QLabel#header { color: #768390; font-size: 8.5pt; }
QLabel#jointName { font-weight: bold; }
QLabel#value { font-family: "DejaVu Sans Mono"; }
QLabel#link { font-weight: bold; color: #e6edf3; }
QLabel#rates { color: #768390; font-family: "DejaVu Sans Mono"; }
QLabel#instruction { font-size: 11pt; color: #e6edf3; padding: 4px; }
QPushButton { background: #2d333b; border: 1px solid #444c56; border-radius: 5px; padding: 5px 12px; }
QPushButton:hover { background: #373e47; }
QPushButton:disabled { color: #545d68; }
QPushButton#estop { background: #c62828; color: white; font-weight: bold; font-size: 13pt;
                    border: 2px solid #ff8a80; border-radius: 8px; padding: 8px 22px; }
QPushButton#estop:hover { background: #e53935; }
QSlider::groove:horizontal { height: 6px; background: #373e47; border-radius: 3px; }
QSlider::handle:horizontal { background: #539bf5; width: 14px; margin: -5px 0; border-radius: 7px; }
QProgressBar { border: 1px solid #373e47; border-radius: 3px; background: #1b1f24; text-align: center;
               font-size: 8pt; max-height: 14px; }
QProgressBar::chunk { background: #347d39; }
QProgressBar[warn="true"]::chunk { background: #c69026; }
QTabWidget::pane { border: 1px solid #373e47; border-radius: 6px; }
QTabBar::tab { background: #2d333b; padding: 6px 14px; border-top-left-radius: 5px; border-top-right-radius: 5px; }
QTabBar::tab:selected { background: #373e47; color: #e6edf3; }
QTableWidget { gridline-color: #373e47; font-family: "DejaVu Sans Mono"; }
QHeaderView::section { background: #2d333b; color: #768390; border: none; padding: 4px; }
QStatusBar { color: #adbac7; }
"""


def joint_colors(joints: list[str]) -> dict[str, QColor]:
    return {name: QColor(JOINT_COLORS[i % len(JOINT_COLORS)]) for i, name in enumerate(joints)}
