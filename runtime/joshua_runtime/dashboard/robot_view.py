"""What the dashboard shows of a robot, read from its build: the manifest and the nodes' entrypoint settings."""

import ast
import json
from dataclasses import dataclass, field
from pathlib import Path

from joshua_core.dashboard import PROCESS_TYPE as DASHBOARD_TYPE
from joshua_runtime.errors import SettingsError

JOINT_STATE = "sensor_msgs/msg/JointState"
IMAGE = "sensor_msgs/msg/Image"
COMPRESSED_IMAGE = "sensor_msgs/msg/CompressedImage"
LASER_SCAN = "sensor_msgs/msg/LaserScan"
# The stream kind each message type is shown as; topics of other types only count messages.
STREAM_KINDS = {JOINT_STATE: "joints", IMAGE: "image", COMPRESSED_IMAGE: "image", LASER_SCAN: "scan"}
RECORDER_TYPE = "DATA_SUBSCRIBER"
INFERENCE_TYPE = "INFERENCE"


@dataclass(frozen=True)
class Stream:
    """One topic the dashboard subscribes to, and how it is shown (`joints`, `image`, `scan` or `rate`)."""

    topic: str
    message_type: str
    kind: str


@dataclass(frozen=True)
class Recorder:
    """A DATA_SUBSCRIBER node: where its dataset lives and the topic its episode commands go to."""

    node: str
    output_directory: str
    command_topic: str
    status_topic: str


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

    def summary(self) -> dict:
        """The JSON the page receives first: everything static about the robot."""
        return {
            "robot": self.robot,
            "topology": self.topology,
            "streams": [{"topic": s.topic, "message_type": s.message_type, "kind": s.kind} for s in self.streams],
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
    streams = tuple(Stream(t["name"], t["message_type"], STREAM_KINDS.get(t["message_type"], "rate")) for t in topics)
    recorders, inferences = [], []
    for node in nodes:
        if node["type"] not in (RECORDER_TYPE, INFERENCE_TYPE):
            continue
        settings = _entrypoint_settings(manifest_path.parent, entrypoints.get(node["name"]))
        if node["type"] == RECORDER_TYPE:
            recorders.append(
                Recorder(
                    node["name"],
                    settings.get("output_directory") or "",
                    f"/{node['name']}/episode",
                    f"/{node['name']}/episode_state",
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
    return RobotView(robot, topology(nodes, processes, topics), streams, tuple(recorders), tuple(inferences))


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
