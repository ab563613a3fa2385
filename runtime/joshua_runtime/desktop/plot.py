"""A fast scrolling strip chart drawn with QPainter: several series over the last few seconds.

Samples are appended as they arrive (any rate); painting happens only when the window's frame timer
asks, and draws at most one point per POINT_SPACING_PX per series, so 100 Hz data costs the same
per frame as 10 Hz data.
"""

import math

import numpy as np
import shiboken6
from PySide6.QtCore import QLineF, QRectF, Qt
from PySide6.QtGui import QColor, QFont, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QSizePolicy, QWidget

WINDOW_S = 10.0
POINT_SPACING_PX = 2
LINE_WIDTH_PX = 1.0  # the raster engine strokes 1 px antialiased lines ~15x faster than 1.6 px ones
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


def polygon(xs: np.ndarray, ys: np.ndarray) -> QPolygonF:
    """A QPolygonF filled straight from arrays (no QPointF object per point)."""
    result = QPolygonF()
    result.resize(len(xs))
    memory = shiboken6.VoidPtr(result.data(), len(xs) * 16, True)  # QPointF = two doubles
    points = np.frombuffer(memory, dtype=np.float64).reshape(len(xs), 2)
    points[:, 0], points[:, 1] = xs, ys
    return result


class StripChart(QWidget):
    """One chart; `append(t, {series: value})`, then `update()` to repaint (the window does it per frame)."""

    def __init__(self, title: str, unit: str, colors: dict[str, QColor], minimum_span: float, parent=None):
        super().__init__(parent)
        self.title, self.unit, self.colors, self.minimum_span = title, unit, colors, minimum_span
        self.names = list(colors)
        self._times = np.zeros(MAX_SAMPLES)
        self._values = np.full((len(self.names), MAX_SAMPLES), np.nan)
        self._count = 0  # samples appended so far; the ring holds the last MAX_SAMPLES
        self.empty_text = "waiting for data"
        self.frames_painted = 0
        self.setMinimumHeight(110)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Expanding)

    def append(self, time_s: float, values: dict[str, float | None]) -> None:
        if all(value is None for value in values.values()):
            return
        slot = self._count % MAX_SAMPLES
        self._times[slot] = time_s
        for row, name in enumerate(self.names):
            value = values.get(name)
            self._values[row, slot] = math.nan if value is None else value
        self._count += 1

    @property
    def times(self) -> np.ndarray:
        """Sample times, oldest first."""
        return self._ordered(self._times)

    def _ordered(self, ring: np.ndarray) -> np.ndarray:
        if self._count <= MAX_SAMPLES:
            return ring[..., : self._count]
        split = self._count % MAX_SAMPLES
        return np.concatenate((ring[..., split:], ring[..., :split]), axis=-1)

    def latest(self, name: str) -> float | None:
        if not self._count:
            return None
        value = self._values[self.names.index(name), (self._count - 1) % MAX_SAMPLES]
        return None if math.isnan(value) else float(value)

    def paintEvent(self, _event) -> None:
        painter = QPainter(self)
        painter.fillRect(self.rect(), BACKGROUND)
        plot = QRectF(
            MARGIN_LEFT,
            MARGIN_TOP,
            self.width() - MARGIN_LEFT - MARGIN_RIGHT,
            self.height() - MARGIN_TOP - MARGIN_BOTTOM,
        )
        font = QFont(self.font())
        font.setPointSizeF(8.5)
        painter.setFont(font)
        painter.setPen(TITLE)
        painter.drawText(
            QRectF(8, 2, plot.right(), MARGIN_TOP - 4), Qt.AlignmentFlag.AlignVCenter, f"{self.title}  [{self.unit}]"
        )
        if self._count < 2 or plot.width() < 10 or plot.height() < 10:
            painter.setPen(TEXT)
            painter.drawText(plot, Qt.AlignmentFlag.AlignCenter, self.empty_text)
            painter.end()
            self.frames_painted += 1
            return
        times, values = self.times, self._ordered(self._values)
        now = times[-1]
        visible = times >= now - WINDOW_S
        stride = max(1, int(visible.sum() * POINT_SPACING_PX / plot.width()))
        index = np.flatnonzero(visible)[::-1][::stride][::-1]
        values = values[:, index]
        finite = values[np.isfinite(values)]
        low, high, step = nice_range(finite.min(), finite.max(), self.minimum_span) if finite.size else (0, 1, 0.5)
        if high - low == 0:
            high = low + step
        self._grid(painter, plot, low, high, step)
        xs = plot.right() - (now - times[index]) / WINDOW_S * plot.width()
        scale = plot.height() / (high - low)
        painter.setClipRect(plot)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)  # for the series only: the grid is axis-aligned
        for name, row in zip(self.names, values):
            ys = plot.bottom() - (row - low) * scale
            known = np.isfinite(ys)
            if known.sum() > 1:
                pen = QPen(self.colors[name], LINE_WIDTH_PX)
                pen.setCosmetic(True)
                painter.setPen(pen)
                painter.drawPolyline(polygon(xs[known], ys[known]))
        painter.end()
        self.frames_painted += 1

    def _grid(self, painter: QPainter, plot: QRectF, low: float, high: float, step: float) -> None:
        count = round((high - low) / step)
        rows = [plot.bottom() - plot.height() * line / count for line in range(count + 1)]
        columns = [plot.right() - plot.width() * second / WINDOW_S for second in range(1, int(WINDOW_S))]
        painter.setPen(QPen(GRID, 1))
        painter.drawLines(
            [QLineF(plot.left(), y, plot.right(), y) for y in rows]
            + [QLineF(x, plot.top(), x, plot.bottom()) for x in columns]
        )
        painter.setPen(TEXT)
        for line, y in enumerate(rows):
            painter.drawText(
                QRectF(0, y - 8, MARGIN_LEFT - 6, 16),
                Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter,
                f"{low + line * step:g}",
            )
        painter.drawText(
            QRectF(plot.left(), plot.bottom() + 2, plot.width(), MARGIN_BOTTOM - 2),
            Qt.AlignmentFlag.AlignLeft,
            f"-{WINDOW_S:g} s",
        )
        painter.drawText(
            QRectF(plot.left(), plot.bottom() + 2, plot.width(), MARGIN_BOTTOM - 2), Qt.AlignmentFlag.AlignRight, "now"
        )
