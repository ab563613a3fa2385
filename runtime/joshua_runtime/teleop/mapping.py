"""What a key or a gamepad means as a body velocity (linear m/s, angular rad/s), pure.

Keys (a terminal reports no key release, so a key sets a motion that lasts until the next key):
    w / up arrow      forward          s / down arrow    backward
    a / left arrow    turn left        d / right arrow   turn right
    q e z c           forward-left, forward-right, backward-left, backward-right
    space or x        stop             + / -             speeds up / down by 10 %
Gamepad: the left stick's vertical axis drives, its horizontal axis turns (pushed left turns left).
"""

from dataclasses import dataclass

# Each motion key: (share of the top linear speed, share of the top angular speed).
MOTIONS = {
    "w": (1, 0),
    "s": (-1, 0),
    "a": (0, 1),
    "d": (0, -1),
    "q": (1, 1),
    "e": (1, -1),
    "z": (-1, -1),
    "c": (-1, 1),
    "\x1b[A": (1, 0),
    "\x1b[B": (-1, 0),
    "\x1b[D": (0, 1),
    "\x1b[C": (0, -1),
    " ": (0, 0),
    "x": (0, 0),
}
SPEED_STEP = 1.1
DEADZONE = 0.05


@dataclass
class KeyboardTeleop:
    """The motion the last key chose, at the present top speeds."""

    max_linear: float
    max_angular: float
    linear_share: float = 0.0
    angular_share: float = 0.0

    def press(self, key: str) -> bool:
        """Apply one key; False when the key means nothing."""
        if key in MOTIONS:
            self.linear_share, self.angular_share = MOTIONS[key]
        elif key == "+":
            self.max_linear, self.max_angular = self.max_linear * SPEED_STEP, self.max_angular * SPEED_STEP
        elif key == "-":
            self.max_linear, self.max_angular = self.max_linear / SPEED_STEP, self.max_angular / SPEED_STEP
        else:
            return False
        return True

    def velocity(self) -> tuple[float, float]:
        return self.linear_share * self.max_linear, self.angular_share * self.max_angular


def joy_velocity(
    axes,
    buttons,
    max_linear: float,
    max_angular: float,
    linear_axis: int = 1,
    angular_axis: int = 0,
    enable_button: int = -1,
) -> tuple[float, float]:
    """The velocity of a Joy message's sticks; zero while the enable button (when one is set) is released."""
    if enable_button >= 0 and (enable_button >= len(buttons) or not buttons[enable_button]):
        return 0.0, 0.0

    def axis(index: int) -> float:
        value = axes[index] if index < len(axes) else 0.0
        return 0.0 if abs(value) < DEADZONE else max(-1.0, min(1.0, value))

    return axis(linear_axis) * max_linear, axis(angular_axis) * max_angular
