"""What the dashboard shows of a robot, read from its build: the manifest and the nodes' entrypoint settings."""

import ast
import json
from dataclasses import dataclass, field
from pathlib import Path

from joshua_core.dashboard import PROCESS_TYPE as DASHBOARD_TYPE
from joshua_core.message_types import IMAGE_TYPES, JOINT_STATE, LASER_SCAN
from joshua_core.node_types import DATA_SUBSCRIBER, INFERENCE
from joshua_runtime.ai import episode_protocol
from joshua_runtime.dashboard.api_schema import named
from joshua_runtime.errors import SettingsError

# The stream kinds of the API (api.schema.json's StreamKind).
JOINTS = named("StreamKind", "joints")
IMAGE = named("StreamKind", "image")
SCAN = named("StreamKind", "scan")
RATE = named("StreamKind", "rate")
# The stream kind each message type is shown as; topics of other types only count messages (RATE).
STREAM_KINDS = {JOINT_STATE: JOINTS, **dict.fromkeys(IMAGE_TYPES, IMAGE), LASER_SCAN: SCAN}
RECORDER_TYPE = DATA_SUBSCRIBER.name
INFERENCE_TYPE = INFERENCE.name
# A stream counts as stale once its newest message is older than STALE_PERIODS of its publisher's
# `rate_hz`, and never sooner than STALE_FLOOR_S; STALE_UNKNOWN_RATE_S when no publisher states a rate.
STALE_PERIODS = 5
STALE_FLOOR_S = 1.5
STALE_UNKNOWN_RATE_S = 3.0


@dataclass(frozen=True)
class Stream:
    """One topic the dashboard subscribes to, how it is shown (a StreamKind of api.schema.json), and
    the rate its publishers state (None when none does)."""

    topic: str
    message_type: str
    kind: str
    expected_hz: float | None = None

    @property
    def stale_after_s(self) -> float:
        if not self.expected_hz:
            return STALE_UNKNOWN_RATE_S
        return max(STALE_FLOOR_S, STALE_PERIODS / self.expected_hz)


@dataclass(frozen=True)
class Process:
    """One process of the supervisor: `critical` ones stop the robot when they fail for good."""

    name: str
    type: str
    critical: bool


@dataclass(frozen=True)
class Recorder:
    """A DATA_SUBSCRIBER node: where its dataset lives, the topic its episode commands go to, its answers
    and its progress reports (ai/episode_protocol.py)."""

    node: str
    output_directory: str
    command_topic: str
    status_topic: str
    progress_topic: str


@dataclass(frozen=True)
class Inference:
    """An INFERENCE node: its model, its input topics and the action topic it publishes."""

    node: str
    model: str
    rate_hz: float
    inputs: tuple[str, ...]
    output: str


@dataclass(frozen=True)
class RobotView:
    """The robot as the page sees it: topology, streams, recorders and inference nodes."""

    robot: str
    topology: dict
    streams: tuple[Stream, ...]
    recorders: tuple[Recorder, ...] = field(default=())
    inferences: tuple[Inference, ...] = field(default=())
    processes: tuple[Process, ...] = field(default=())

    @property
    def dashboard_process(self) -> str | None:
        """The process serving the dashboard (stopping it closes the page's connection)."""
        return next((p.name for p in self.processes if p.type == DASHBOARD_TYPE), None)

    def summary(self) -> dict:
        """The JSON the page receives first: everything static about the robot."""
        return {
            "robot": self.robot,
            "topology": self.topology,
            "streams": [
                {"topic": s.topic, "message_type": s.message_type, "kind": s.kind, "stale_after_s": s.stale_after_s}
                for s in self.streams
            ],
            "processes": [{"name": p.name, "type": p.type, "critical": p.critical} for p in self.processes],
            "dashboard_process": self.dashboard_process,
            "recorders": [{"node": r.node, "output_directory": r.output_directory} for r in self.recorders],
            "inferences": [
                {"node": i.node, "model": i.model, "rate_hz": i.rate_hz, "inputs": list(i.inputs), "output": i.output}
                for i in self.inferences
            ],
        }


def load_robot_view(manifest_path: Path) -> RobotView:
    """Read OUT/manifest.json (and OUT/nodes/*.py for recorder and inference settings)."""
    try:
        manifest = json.loads(manifest_path.read_text())
        robot = manifest["robot"]["name"]
        nodes, topics, processes = manifest["nodes"], manifest["topics"], manifest["processes"]
    except OSError as exc:
        raise SettingsError(f"cannot read manifest {manifest_path}: {exc.strerror}") from exc
    except (ValueError, KeyError, TypeError) as exc:
        raise SettingsError(f"{manifest_path} is not a joshuac manifest: {exc}") from exc
    entrypoints = {p["name"]: p.get("entrypoint") for p in processes}
    settings_of = _settings_reader(manifest_path.parent, nodes, entrypoints)
    streams = tuple(
        Stream(t["name"], t["message_type"], kind, _stated_rate(t, settings_of) if kind != RATE else None)
        for t in topics
        for kind in [STREAM_KINDS.get(t["message_type"], RATE)]
    )
    recorders, inferences = [], []
    for node in nodes:
        if node["type"] not in (RECORDER_TYPE, INFERENCE_TYPE):
            continue
        settings = settings_of(node["name"])
        if node["type"] == RECORDER_TYPE:
            recorders.append(
                Recorder(
                    node["name"],
                    settings.get("output_directory") or "",
                    *(
                        episode_protocol.topic(node["name"], relative)
                        for relative in (
                            episode_protocol.COMMAND_TOPIC,
                            episode_protocol.STATE_TOPIC,
                            episode_protocol.PROGRESS_TOPIC,
                        )
                    ),
                )
            )
        else:
            inferences.append(
                Inference(
                    node["name"],
                    settings.get("model_path") or "",
                    float(settings.get("rate_hz") or 0),
                    tuple(node["subscribes"]),
                    (node["publishes"] or [""])[0],
                )
            )
    return RobotView(
        robot,
        topology(nodes, processes, topics),
        streams,
        tuple(recorders),
        tuple(inferences),
        tuple(Process(p["name"], p["type"], bool(p.get("critical", p["type"] != DASHBOARD_TYPE))) for p in processes),
    )


def _settings_reader(build_directory: Path, nodes: list[dict], entrypoints: dict):
    """settings_of(node name) -> the node's resolved settings: its entrypoint's SETTINGS, or its entry in
    the SETTINGS of the process that simulates it; empty when neither has them. Each file is read once."""
    simulated_by = {n["name"]: n.get("simulated_by") for n in nodes}
    read: dict[str, dict] = {}

    def process_settings(process: str) -> dict:
        if process not in read:
            read[process] = _entrypoint_settings(build_directory, entrypoints.get(process))
        return read[process]

    def settings_of(node: str) -> dict:
        host = simulated_by.get(node)
        if not host:
            return process_settings(node)
        simulates = (process_settings(host).get("simulation") or {}).get("simulates") or []
        return next((s for s in simulates if isinstance(s, dict) and s.get("name") == node), {})

    return settings_of


def _stated_rate(topic: dict, settings_of) -> float | None:
    """The highest `rate_hz` the topic's publishers state, or None."""
    rates = [settings_of(p["node"]).get("rate_hz") for p in topic.get("publishers", [])]
    rates = [float(r) for r in rates if isinstance(r, int | float) and r > 0]
    return max(rates, default=None)


def topology(nodes: list[dict], processes: list[dict], topics: list[dict]) -> dict:
    """Nodes, topics and edges of the graph the page draws (node -> topic for publishers, topic -> node for subscribers)."""
    return {
        "nodes": [{"name": n["name"], "type": n["type"], "process": n["simulated_by"] or n["name"]} for n in nodes]
        + [
            {"name": p["name"], "type": p["type"], "process": p["name"]}
            for p in processes
            if p["name"] not in {n["name"] for n in nodes} and p["type"] != DASHBOARD_TYPE
        ],
        "topics": [{"name": t["name"], "message_type": t["message_type"]} for t in topics],
        "edges": [{"from": n["name"], "to": topic} for n in nodes for topic in n["publishes"]]
        + [{"from": topic, "to": n["name"]} for n in nodes for topic in n["subscribes"]],
    }


def _entrypoint_settings(build_directory: Path, entrypoint: str | None) -> dict:
    """The SETTINGS literal of a generated entrypoint; empty when the node has none (a C++ or custom node)."""
    if not entrypoint:
        return {}
    path = build_directory / entrypoint
    try:
        module = ast.parse(path.read_text(), str(path))
    except (OSError, SyntaxError):
        return {}
    for statement in module.body:
        if isinstance(statement, ast.Assign) and any(getattr(t, "id", "") == "SETTINGS" for t in statement.targets):
            try:
                return ast.literal_eval(statement.value)
            except ValueError:
                return {}
    return {}
