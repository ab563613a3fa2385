"""The frozen model of a checked description: nodes with derived names, topics, processes, devices.

`plan(description)` is pure; it assumes the rules found no error, so every value is valid here.
"""

from dataclasses import dataclass, field, replace
from functools import cached_property

from joshua_core.control_plane import PROCESS_TYPE as HOST_AGENT_TYPE
from joshua_core.dashboard import PROCESS_TYPE as DASHBOARD_TYPE
from joshua_core.discovery import PROCESS_TYPE as DISCOVERY_TYPE
from joshua_core.node_types import FOXGLOVE_BRIDGE, SIMULATION_ENGINE
from joshua_core.settings import FORMAT_VERSION, NodeSettings


@dataclass(frozen=True)
class QoS:
    history: str
    depth: int
    reliability: str
    durability: str

    def as_dict(self) -> dict:
        return {
            "history": self.history,
            "depth": self.depth,
            "reliability": self.reliability,
            "durability": self.durability,
        }


@dataclass(frozen=True)
class Endpoint:
    """One node's publisher or subscription on one topic."""

    node: str
    topic: str
    message_type: str
    qos: QoS
    role: str  # "publisher" | "subscriber"

    def as_topic_settings(self) -> dict:
        return {"name": self.topic, "message_type": self.message_type, "qos": self.qos.as_dict()}


@dataclass(frozen=True)
class Topic:
    name: str
    message_type: str
    publishers: tuple[Endpoint, ...]
    subscribers: tuple[Endpoint, ...]


@dataclass(frozen=True)
class Device:
    """Something on the robot a node needs before it starts: `serial`, `camera`, `file`, `model`."""

    kind: str
    path: str
    node: str


@dataclass(frozen=True)
class Process:
    """What the supervisor starts for one node.

    `python` processes run `nodes/<name>.py`; `custom` ones run `executable` with `args`. When
    `cpp_binary` is set, the supervisor prefers `<cpp_bin_dir>/<cpp_binary>` with `cpp_args`.
    A custom process counts as carrying images: the topics it declares need not be all it uses.
    `inputs` are the files it reads as it starts (as the description names them, relative to the
    directory the robot runs in): a reload restarts it when one of them changed since its start.
    """

    name: str
    node_type: str
    kind: str  # "python" | "custom"
    entrypoint: str  # path relative to the output directory
    executable: str
    args: tuple[str, ...]
    cpp_binary: str
    cpp_args: tuple[str, ...]
    restart: str
    max_restarts: int
    critical: bool
    env: tuple[tuple[str, str], ...]
    devices: tuple[Device, ...]
    carries_images: bool  # publishes or subscribes images, so DDS must fit them in shared memory
    host: str = ""  # the computer it runs on ("" without hosts)
    starts_first: bool = False  # the supervisor starts the others once it is ready (the Discovery Server)
    inputs: tuple[str, ...] = ()


@dataclass(frozen=True)
class NodeModel:
    name: str
    type: str
    index: int  # position among the description's nodes
    backend: str  # "PYTHON" | "CPP" (the preference the node type honours)
    simulated_by: str  # the process standing in for it in MODE_SIMULATION, else ""
    publishes: tuple[Endpoint, ...]
    subscribes: tuple[Endpoint, ...]
    devices: tuple[Device, ...]
    settings: NodeSettings = field(hash=False, compare=False)  # written into its entrypoint (node_settings.py)
    host: str = ""  # the computer it runs on ("" without hosts)


@dataclass(frozen=True)
class Host:
    """One computer of a robot on several (`host { }`)."""

    name: str
    address: str
    ros_from_system: bool
    python: str  # the interpreter its install.sh makes the environment with ("" for the bundle's default)


@dataclass(frozen=True)
class DiscoveryServer:
    """The Fast DDS Discovery Server every process uses (`discovery { }`)."""

    host: str
    address: str
    port: int


@dataclass(frozen=True)
class ControlRouter:
    """Where the hosts' agents meet (`control { }`): the host whose agent listens, and its Zenoh endpoint."""

    host: str
    endpoint: str


@dataclass(frozen=True)
class Robot:
    name: str
    mode: str
    source: str  # file name of the description, without directories
    nodes: tuple[NodeModel, ...]
    topics: tuple[Topic, ...]
    processes: tuple[Process, ...]
    sigint_grace_s: float
    sigterm_grace_s: float
    ros_domain_id: int | None
    cpp_bin_dir: str
    python_executable: str
    env: tuple[tuple[str, str], ...]
    simulation: NodeSettings | None = field(hash=False, compare=False)  # the engine's settings in MODE_SIMULATION
    foxglove: NodeSettings | None = field(default=None, hash=False, compare=False)  # the Foxglove bridge's
    hosts: tuple[Host, ...] = ()  # the computers it runs on; () for one computer
    discovery: DiscoveryServer | None = None
    control: ControlRouter | None = None
    host: str = ""  # the one host this model's processes are restricted to (for_host), else ""
    # The host of every process of the whole robot by process name, in start order (kept by for_host).
    placement: dict[str, str] = field(default_factory=dict, hash=False, compare=False)

    @property
    def this_host(self) -> Host | None:
        """The host a part made by for_host runs on (None for the whole robot)."""
        return next((host for host in self.hosts if host.name == self.host), None)

    def for_host(self, name: str) -> "Robot":
        """The part of the robot one host runs: its nodes and processes (topics stay whole)."""
        return replace(
            self,
            nodes=tuple(node for node in self.nodes if node.host == name),
            processes=tuple(process for process in self.processes if process.host == name),
            host=name,
        )

    def node(self, name: str) -> NodeModel:
        return self._nodes_by_name[name]

    @cached_property
    def _nodes_by_name(self) -> dict[str, NodeModel]:
        return {node.name: node for node in self.nodes}

    def simulated_by(self, process: str) -> list[NodeModel]:
        """The described nodes a simulation process stands in for."""
        return self._simulated.get(process, [])

    @cached_property
    def _simulated(self) -> dict[str, list[NodeModel]]:
        simulated: dict[str, list[NodeModel]] = {}
        for node in self.nodes:
            if node.simulated_by:
                simulated.setdefault(node.simulated_by, []).append(node)
        return simulated

    def process_settings(self, process: Process) -> NodeSettings:
        """The settings of a python process (a node's, or the simulation engine's); the dashboard's, the
        Discovery Server's and the host agents' name only their process (their entrypoints hold command-line
        arguments instead)."""
        if process.node_type in (DASHBOARD_TYPE, DISCOVERY_TYPE, HOST_AGENT_TYPE):
            return NodeSettings(
                format_version=FORMAT_VERSION,
                robot=self.name,
                mode=self.mode,
                name=process.name,
                type=process.node_type,
            )
        if process.node_type == SIMULATION_ENGINE.name:
            return self.simulation
        if process.node_type == FOXGLOVE_BRIDGE.name:
            return self.foxglove
        return self.node(process.name).settings
