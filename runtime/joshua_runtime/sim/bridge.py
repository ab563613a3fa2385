"""What a simulation bridge is: the ROS side of one simulated hardware node, one class per module in sim/bridges/.

A hardware node type's registry entry names its bridge (`sim_bridge`, `module:Class`); the SIMULATION
node builds one per replaced node from that node's own settings, on its topics, message types and
QoS, with the units of the real drivers. A bridge subclasses SimulationBridge and keeps its defaults
unless it renders (a camera: `streams`) or has something to say when the run ends (`summary`).
"""

import importlib
from typing import TYPE_CHECKING, Protocol

from joshua_core.node_types import spec
from joshua_core.settings import NodeSettings
from joshua_runtime.errors import SettingsError

if TYPE_CHECKING:
    from joshua_runtime.sim.cameras import CameraStream
    from joshua_runtime.sim.engine import SimulationEngine
    from joshua_runtime.sim.engine_node import SimulationEngineNode


class SimulationBridge(Protocol):
    """Built as `Bridge(node, engine, settings)`: publishes and subscribes on behalf of one simulated node."""

    def __init__(self, node: "SimulationEngineNode", engine: "SimulationEngine", settings: NodeSettings) -> None: ...

    @property
    def streams(self) -> "tuple[CameraStream, ...]":
        """What the engine's render thread draws for this bridge (cameras); none by default."""
        return ()

    def summary(self) -> str:
        """What the engine's last log line says about this bridge when the run ends ("" for nothing)."""
        return ""


def bridge_class(node_type: str) -> type[SimulationBridge]:
    """The bridge class the registry names for a node type; SettingsError when it cannot be simulated."""
    entry = spec(node_type)
    if entry is None or not entry.sim_bridge:
        raise SettingsError(f"node type {node_type} cannot be simulated")
    module_name, class_name = entry.sim_bridge.split(":")
    return getattr(importlib.import_module(module_name), class_name)


def make_bridge(node: "SimulationEngineNode", engine: "SimulationEngine", settings: NodeSettings) -> SimulationBridge:
    """The bridge that stands in for one hardware node, built from its settings."""
    try:
        bridge = bridge_class(settings.type)
    except SettingsError as exc:
        raise SettingsError(f"{settings.name}: {exc}") from exc
    return bridge(node, engine, settings)
