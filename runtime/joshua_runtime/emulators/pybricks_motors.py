"""Motor model of the emulated Pybricks hub: each wheel motor ramps its speed toward the commanded one."""

from dataclasses import dataclass

# How fast a motor changes speed, deg/s per second (Pybricks' default acceleration for medium motors).
ACCELERATION_DPS2 = 2000.0
# Fastest speed a motor reaches, deg/s.
MAX_SPEED_DPS = 1000.0


@dataclass
class Motor:
    target_dps: float = 0.0
    speed_dps: float = 0.0
    angle_deg: float = 0.0

    def run(self, speed_dps: float) -> None:
        self.target_dps = max(-MAX_SPEED_DPS, min(MAX_SPEED_DPS, speed_dps))

    def stop(self) -> None:
        self.target_dps = 0.0

    def step(self, dt_s: float) -> None:
        """Advance the motor by dt_s: speed ramps toward the target, the angle integrates the speed."""
        change = self.target_dps - self.speed_dps
        limit = ACCELERATION_DPS2 * dt_s
        new_speed = self.speed_dps + max(-limit, min(limit, change))
        self.angle_deg += 0.5 * (self.speed_dps + new_speed) * dt_s
        self.speed_dps = new_speed
