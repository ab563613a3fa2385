"""A fast scrolling strip chart drawn with QPainter: several series over the last few seconds.

Samples are appended as they arrive (any rate); painting happens only when the window's frame timer
asks, and draws at most one point per POINT_SPACING_PX per series, so 100 Hz data costs the same
per frame as 10 Hz data.
"""

import math
from collections import deque

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QFont, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QSizePolicy, QWidget

WINDOW_S = 10.0
POINT_SPACING_PX = 2
MAX_SAMPLES = 4096
MARGIN_LEFT, MARGIN_RIGHT, MARGIN_TOP, MARGIN_BOTTOM = 46, 10, 30, 18
GRID_LINES = 4
BACKGROUND = QColor("#1b1f24")
GRID = QColor("#2d333b")
TEXT = QColor("#adbac7")
TITLE = QColor("#e6edf3")


def nice_step(span: float) -> float:
    """A round grid step (1, 2 or 5 times a power of ten) giving about GRID_LINES lines over `span`."""
    rough = span / GRID_LINES
    power = 10 ** math.floor(math.log10(rough))
    return next(m * power for m in (1, 2, 5, 10) if m * power >= rough)


def nice_range(low: float, high: float, minimum_span: float) -> tuple[float, float, float]:
    """An axis (low, high, step) on round values that covers [low, high] and spans at least `minimum_span`."""
    if not math.isfinite(low) or not math.isfinite(high):
        low, high = 0.0, minimum_span
    middle, span = (low + high) / 2, max(high - low, minimum_span)
    step = nice_step(span)
    return math.floor((middle - span / 2) / step) * step, math.ceil((middle + span / 2) / step) * step, step


class StripChart(QWidget):
    """One chart; `append(t, {series: value})`, then `update()` to repaint (the window does it per frame)."""

    def __init__(self, title: str, unit: str, colors: dict[str, QColor], minimum_span: float, parent=None):
        super().__init__(parent)
        self.title, self.unit, self.colors, self.minimum_span = title, unit, colors, minimum_span
        self.times: deque = deque(maxlen=MAX_SAMPLES)
        self.values = {name: deque(maxlen=MAX_SAMPLES) for name in colors}
        self.empty_text = "waiting for data"
        self.frames_painted = 0
        self.setMinimumHeight(110)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Expanding)

    def append(self, time_s: float, values: dict[str, float | None]) -> None:
        if all(value is None for value in values.values()):
            return
        self.times.append(time_s)
        for name, series in self.values.items():
            value = values.get(name)
            series.append(math.nan if value is None else float(value))

    def latest(self, name: str) -> float | None:
        series = self.values.get(name)
        return series[-1] if series else None

    def paintEvent(self, _event) -> None:
        painter = QPainter(self)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        painter.fillRect(self.rect(), BACKGROUND)
        plot = QRectF(MARGIN_LEFT, MARGIN_TOP, self.width() - MARGIN_LEFT - MARGIN_RIGHT,
                      self.height() - MARGIN_TOP - MARGIN_BOTTOM)
        font = QFont(self.font())
        font.setPointSizeF(8.5)
        painter.setFont(font)
        painter.setPen(TITLE)
        painter.drawText(QRectF(8, 2, plot.right(), MARGIN_TOP - 4), Qt.AlignmentFlag.AlignVCenter,
                         f"{self.title}  [{self.unit}]")
        if len(self.times) < 2 or plot.width() < 10 or plot.height() < 10:
            painter.setPen(TEXT)
            painter.drawText(plot, Qt.AlignmentFlag.AlignCenter, self.empty_text)
            painter.end()
            self.frames_painted += 1
            return
        times = np.fromiter(self.times, float, len(self.times))
        now = times[-1]
        visible = times >= now - WINDOW_S
        stride = max(1, int(visible.sum() * POINT_SPACING_PX / plot.width()))
        index = np.flatnonzero(visible)[::-1][::stride][::-1]
        series = {name: np.fromiter(values, float, len(values))[index] for name, values in self.values.items()}
        finite = np.concatenate([v[np.isfinite(v)] for v in series.values()] + [np.empty(0)])
        low, high, step = nice_range(finite.min(), finite.max(), self.minimum_span) if finite.size else (0, 1, 0.5)
        if high - low == 0:
            high = low + step
        self._grid(painter, plot, low, high, step)
        xs = plot.right() - (now - times[index]) / WINDOW_S * plot.width()
        scale = plot.height() / (high - low)
        painter.setClipRect(plot)
        for name, values in series.items():
            ys = plot.bottom() - (values - low) * scale
            pen = QPen(self.colors[name], 1.6)
            painter.setPen(pen)
            points = [QPointF(x, y) for x, y in zip(xs.tolist(), ys.tolist()) if y == y]
            if len(points) > 1:
                painter.drawPolyline(QPolygonF(points))
        painter.end()
        self.frames_painted += 1

    def _grid(self, painter: QPainter, plot: QRectF, low: float, high: float, step: float) -> None:
        lines = round((high - low) / step)
        for line in range(lines + 1):
            value = low + line * step
            y = plot.bottom() - plot.height() * line / lines
            painter.setPen(QPen(GRID, 1))
            painter.drawLine(QPointF(plot.left(), y), QPointF(plot.right(), y))
            painter.setPen(TEXT)
            painter.drawText(QRectF(0, y - 8, MARGIN_LEFT - 6, 16),
                             Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter, f"{value:g}")
        painter.setPen(QPen(GRID, 1))
        for second in range(1, int(WINDOW_S)):
            x = plot.right() - plot.width() * second / WINDOW_S
            painter.drawLine(QPointF(x, plot.top()), QPointF(x, plot.bottom()))
        painter.setPen(TEXT)
        painter.drawText(QRectF(plot.left(), plot.bottom() + 2, plot.width(), MARGIN_BOTTOM - 2),
                         Qt.AlignmentFlag.AlignLeft, f"-{WINDOW_S:g} s")
        painter.drawText(QRectF(plot.left(), plot.bottom() + 2, plot.width(), MARGIN_BOTTOM - 2),
                         Qt.AlignmentFlag.AlignRight, "now")
