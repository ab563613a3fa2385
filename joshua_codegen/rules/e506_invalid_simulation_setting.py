"""E506 invalid-simulation-setting: a simulation setting outside what MuJoCo can use.

What it checks:
    In `simulation`: `timestep_s`, when set, is a finite number above 0 and at most 1 s;
    `realtime_factor`, when set, is finite and from 0 to 1000 (0 = as fast as possible);
    `gl_backend` is empty, `egl` or `osmesa`; a `builtin:` model names a model joshua_runtime ships.

Why it matters:
    MuJoCo would diverge or refuse to render; these values are only read when the simulation
    starts, so the error would otherwise come late.

Example:
    simulation {
      model: "builtin:so100"
      timestep_s: 0              # error: timestep_s must be above 0 and at most 1 s, got 0
    }
"""

import math

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.models import BUILTIN_MODELS, BUILTIN_PREFIX, GL_BACKENDS

CODE = "E506"
NAME = "invalid-simulation-setting"
SEVERITY = ERROR
STAGE = "check"
MAX_TIMESTEP_S = 1.0
MAX_REALTIME_FACTOR = 1000.0
SIMULATION = ROBOT + ("simulation",)


def check(ctx):
    sim = ctx.config.simulation
    if sim.HasField("timestep_s") and not (math.isfinite(sim.timestep_s) and 0 < sim.timestep_s <= MAX_TIMESTEP_S):
        yield Finding(
            SIMULATION + ("timestep_s",),
            f"timestep_s must be above 0 and at most {MAX_TIMESTEP_S:g} s, got {sim.timestep_s:g}",
        )
    if sim.HasField("realtime_factor") and not (
        math.isfinite(sim.realtime_factor) and 0 <= sim.realtime_factor <= MAX_REALTIME_FACTOR
    ):
        yield Finding(
            SIMULATION + ("realtime_factor",),
            f"realtime_factor must be from 0 to {MAX_REALTIME_FACTOR:g}, got {sim.realtime_factor:g}",
        )
    if sim.gl_backend and sim.gl_backend not in GL_BACKENDS:
        yield Finding(
            SIMULATION + ("gl_backend",), f'unknown gl_backend "{sim.gl_backend}"; use one of {", ".join(GL_BACKENDS)}'
        )
    if sim.model.startswith(BUILTIN_PREFIX) and sim.model[len(BUILTIN_PREFIX) :] not in BUILTIN_MODELS:
        known = ", ".join(f'"{BUILTIN_PREFIX}{name}"' for name in BUILTIN_MODELS)
        yield Finding(SIMULATION + ("model",), f'model "{sim.model}" is not a built-in model; built-in: {known}')
