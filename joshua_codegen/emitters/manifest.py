"""manifest.json: the topology as data (nodes, topics with publishers/subscribers and QoS, devices)."""

import json

from joshua_codegen.model import Endpoint, Robot
from joshua_codegen.render import Context, template

MANIFEST_FORMAT = 1


def _endpoint(endpoint: Endpoint) -> dict:
    return {"node": endpoint.node, "message_type": endpoint.message_type, "qos": endpoint.qos.as_dict()}


def manifest(robot: Robot, context: Context) -> dict:
    """The manifest as plain data."""
    processes = {process.name: process for process in robot.processes}
    return {
        "generator": "joshuac",
        "format": MANIFEST_FORMAT,
        "source": robot.source,
        "prefix": context.prefix,
        "robot": {
            "name": robot.name,
            "mode": robot.mode,
            "ros_domain_id": robot.ros_domain_id,
            "shutdown": {"sigint_grace_s": robot.sigint_grace_s, "sigterm_grace_s": robot.sigterm_grace_s},
            "cpp_bin_dir": robot.cpp_bin_dir,
        },
        "nodes": [
            {
                "name": node.name,
                "type": node.type,
                "backend": node.backend,
                "simulated_by": node.simulated_by or None,
                "process": node.name in processes,
                "restart": processes[node.name].restart if node.name in processes else None,
                "max_restarts": processes[node.name].max_restarts if node.name in processes else None,
                "publishes": [e.topic for e in node.publishes],
                "subscribes": [e.topic for e in node.subscribes],
                "devices": [{"kind": d.kind, "path": d.path} for d in node.devices],
            }
            for node in robot.nodes
        ],
        "processes": [
            {
                "name": process.name,
                "type": process.node_type,
                "kind": process.kind,
                "entrypoint": process.entrypoint or None,
                "executable": process.executable or None,
                "args": list(process.args),
                "cpp_binary": process.cpp_binary or None,
                "simulates": [node.name for node in robot.simulated_by(process.name)],
            }
            for process in robot.processes
        ],
        "topics": [
            {
                "name": topic.name,
                "message_type": topic.message_type,
                "publishers": [_endpoint(e) for e in topic.publishers],
                "subscribers": [_endpoint(e) for e in topic.subscribers],
            }
            for topic in robot.topics
        ],
        # What the robot needs to run: the devices of simulated nodes are not opened.
        "devices": [
            {"kind": d.kind, "path": d.path, "node": d.node} for process in robot.processes for d in process.devices
        ],
    }


def emit(robot: Robot, context: Context) -> dict[str, str]:
    text = json.dumps(manifest(robot, context), indent=2, ensure_ascii=True)
    return {"manifest.json": template("manifest.json.j2", manifest_json=text)}
