"""The SIMULATION node: one process that stands in for every hardware node of a MODE_SIMULATION robot.

Its settings carry `simulation = {"model", "timestep_s", "realtime_factor", "camera", "gl_backend",
"simulates": [settings of each replaced node]}`. It loads the model, starts physics, and builds one
bridge per replaced node (sim/bridge.py; the registry names each type's) on that node's own topics,
types and QoS, and publishes /diagnostics for the servo nodes among them (sim/diagnostics.py).
The bridges' render streams are drawn in their own thread; everything else runs on the node's ROS timers.
"""

from joshua_core.message_types import IMAGE_TYPES
from joshua_runtime.errors import SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.sim.gl_backend import configure_gl


class SimulationEngineNode(JoshuaNode):
    """Runs the MuJoCo engine and publishes/subscribes on behalf of the simulated hardware nodes."""

    engine = None
    cameras = None
    bridges: list = []

    def start(self) -> None:
        if not self.settings.HasField("simulation"):
            raise SettingsError(f"{self.name}: settings have no 'simulation' section")
        sim = self.settings.simulation
        simulated = list(sim.simulates)
        # A simulated node that publishes images is rendered: the GL backend is chosen before mujoco loads.
        renders = any(s.topic.message_type in IMAGE_TYPES for s in simulated)
        gl_backend = configure_gl(sim.gl_backend) if renders else ""

        # mujoco is imported only now, after the GL backend is chosen.
        from joshua_runtime.sim.bridge import make_bridge
        from joshua_runtime.sim.cameras import CameraThread
        from joshua_runtime.sim.diagnostics import SimulatedDiagnostics
        from joshua_runtime.sim.engine import SimulationEngine
        from joshua_runtime.sim.model import load_model

        model = load_model(sim.model, sim.timestep_s if sim.HasField("timestep_s") else None)
        self.engine = SimulationEngine(model, sim.realtime_factor)
        self.default_camera = sim.camera  # the MJCF camera of camera nodes whose frame_id names none
        self.bridges = [make_bridge(self, self.engine, s) for s in simulated]
        self.diagnostics = SimulatedDiagnostics(self, self.engine, simulated)
        streams = [stream for bridge in self.bridges for stream in bridge.streams]
        self.cameras = CameraThread(self.engine, streams, gl_backend)
        # Cameras first: creating GL contexts holds the interpreter for a while, which would show
        # up as time the physics schedule has to drop.
        self.cameras.start()
        self.engine.start()
        self.log.info(
            f"simulating {', '.join(s.name for s in simulated) or 'no nodes'} with {sim.model} "
            f"(timestep {model.opt.timestep} s, realtime factor {self.engine.realtime_factor}"
            + (f", GL {gl_backend})" if gl_backend else ")")
        )

    def close(self) -> None:
        if self.cameras is not None:
            self.cameras.stop()
        if self.engine is not None:
            self.engine.stop()
            if self.engine.started:
                self.log.info(self.summary())

    def summary(self) -> str:
        """One line on how the run went: real-time factor reached, time dropped, frames rendered."""
        sim_s, wall_s = self.engine.run_stats()
        factor = sim_s / wall_s if wall_s > 0 else 0.0
        line = (
            f"stopped: simulated {sim_s:.3f} s in {wall_s:.3f} s (real-time factor {factor:.3f}), "
            f"{self.engine.dropped_s:.3f} s dropped"
        )
        for bridge in self.bridges:
            if said := bridge.summary():
                line += f"; {said}"
        return line
