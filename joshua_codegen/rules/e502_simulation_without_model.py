"""E502 simulation-without-model: MODE_SIMULATION with no simulation.model.

What it checks:
    A description in MODE_SIMULATION sets `simulation { model: ... }`: `builtin:so100` or the
    path of an MJCF file on the robot.

Why it matters:
    The simulation engine replaces the hardware nodes; without a model there is nothing to simulate.

Example:
    robot_config {
      mode: MODE_SIMULATION      # error: MODE_SIMULATION needs simulation.model
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E502"
NAME = "simulation-without-model"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    if ctx.config.mode == pb.MODE_SIMULATION and not ctx.config.simulation.model:
        where = ROBOT + ("simulation",) if ctx.written(ROBOT + ("simulation",)) else ROBOT + ("mode",)
        yield Finding(where, 'MODE_SIMULATION needs simulation.model (e.g. simulation { model: "builtin:so100" })')
