"""Simulation tests: choose the offscreen GL backend before any test module imports mujoco."""

from joshua_runtime.sim.gl_backend import configure_gl

configure_gl("egl")
