"""E130 foxglove-port-out-of-range: `foxglove { port }` is 0 or above 65535.

What it checks:
    `foxglove.port`, when set, is a TCP port: 1 to 65535.

Why it matters:
    The Foxglove bridge process could not listen, and would fail at every restart.

Example:
    robot_config {
      foxglove { port: 70000 }      # error: foxglove port 70000 is out of range 1-65535
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E130"
NAME = "foxglove-port-out-of-range"
SEVERITY = ERROR
STAGE = "check"
MAX_PORT = 65535


def check(ctx):
    foxglove = ctx.config.foxglove
    if ctx.config.HasField("foxglove") and foxglove.HasField("port") and not 1 <= foxglove.port <= MAX_PORT:
        yield Finding(ROBOT + ("foxglove", "port"), f"foxglove port {foxglove.port} is out of range 1-{MAX_PORT}")
