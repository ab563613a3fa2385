"""A PNG of predicted against recorded actions, one panel per joint, drawn with Pillow."""

from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

PANEL_WIDTH, PANEL_HEIGHT, MARGIN, LABEL_HEIGHT = 900, 150, 50, 18
BACKGROUND, AXIS, BOUNDARY = (255, 255, 255), (90, 90, 90), (200, 200, 200)
RECORDED, PREDICTED, MEAN = (31, 119, 180), (214, 39, 40), (120, 120, 120)


def write(
    path: Path,
    joints: list[str],
    recorded: np.ndarray,
    predicted: np.ndarray,
    mean_action: np.ndarray,
    episode_starts: list[int],
    title: str,
) -> Path:
    """Plot `recorded` and `predicted` (frames x joints) and the mean action per joint into the PNG at `path`.

    Vertical lines mark where each held-out episode starts (`episode_starts`, frame indices)."""
    height = LABEL_HEIGHT + len(joints) * (PANEL_HEIGHT + LABEL_HEIGHT) + MARGIN // 2
    image = Image.new("RGB", (PANEL_WIDTH + 2 * MARGIN, height), BACKGROUND)
    draw = ImageDraw.Draw(image)
    font = ImageFont.load_default()
    draw.text((MARGIN, 2), f"{title}   recorded (blue), predicted (red), mean action (grey)", fill=AXIS, font=font)
    frames = recorded.shape[0]
    for row, joint in enumerate(joints):
        top = LABEL_HEIGHT + row * (PANEL_HEIGHT + LABEL_HEIGHT) + LABEL_HEIGHT
        series = (recorded[:, row], predicted[:, row], np.full(frames, mean_action[row]))
        low, high = _range(series)
        draw.text((MARGIN, top - LABEL_HEIGHT + 3), f"{joint}   [{low:.3g}, {high:.3g}]", fill=AXIS, font=font)
        draw.rectangle((MARGIN, top, MARGIN + PANEL_WIDTH, top + PANEL_HEIGHT), outline=AXIS)
        for start in episode_starts[1:]:
            x = MARGIN + PANEL_WIDTH * start / max(frames - 1, 1)
            draw.line((x, top, x, top + PANEL_HEIGHT), fill=BOUNDARY)
        for values, colour in zip(series, (RECORDED, PREDICTED, MEAN)):
            draw.line(_points(values, low, high, top), fill=colour, width=2)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    image.save(path, format="PNG")
    return path


def _range(series) -> tuple[float, float]:
    low = float(min(np.min(values) for values in series))
    high = float(max(np.max(values) for values in series))
    if high - low < 1e-9:
        low, high = low - 1.0, high + 1.0
    pad = 0.05 * (high - low)
    return low - pad, high + pad


def _points(values: np.ndarray, low: float, high: float, top: int) -> list[tuple[float, float]]:
    count = max(len(values) - 1, 1)
    return [
        (MARGIN + PANEL_WIDTH * index / count, top + PANEL_HEIGHT * (high - float(value)) / (high - low))
        for index, value in enumerate(values)
    ]
