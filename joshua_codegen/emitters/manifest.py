"""manifest.json: the topology as data (nodes, topics with publishers/subscribers and QoS, devices)."""

from joshua_codegen.escape import json_document
from joshua_codegen.model import Endpoint, Robot
from joshua_codegen.render import Context, template

MANIFEST_FORMAT = 1


def _endpoint(endpoint: Endpoint) -> dict:
    return {"node": endpoint.node, "message_type": endpoint.message_type, "qos": endpoint.qos.as_dict()}


def manifest(robot: Robot, context: Context) -> dict:
    """The manifest as plain data; with hosts, each node and process says which host runs it."""
    data = _manifest(robot, context)
    if robot.hosts:
        _add_placement(robot, data)
    return data


def _add_placement(robot: Robot, data: dict) -> None:
    """The hosts (with the processes each runs, so that every host's supervisor knows where the others are),
    the Discovery Server, the control plane's router, and each node's and process's host; in one host's
    output, which host it is."""
    if robot.host:
        data["host"] = robot.host
    data["hosts"] = [
        {
            "name": host.name,
            "address": host.address,
            "ros_from_system": host.ros_from_system,
            "processes": [p for p in robot.placement if robot.placement[p] == host.name],
        }
        for host in robot.hosts
    ]
    data["discovery"] = (
        {"host": robot.discovery.host, "address": robot.discovery.address, "port": robot.discovery.port}
        if robot.discovery
        else None
    )
    data["control"] = {"host": robot.control.host, "endpoint": robot.control.endpoint} if robot.control else None
    hosts = {node.name: node.host for node in robot.nodes}
    for node in data["nodes"]:
        node["host"] = hosts[node["name"]]
    for process in data["processes"]:
        process["host"] = robot.placement[process["name"]]
    for device in data["devices"]:
        device["host"] = hosts[device["node"]]


def _manifest(robot: Robot, context: Context) -> dict:
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
                "critical": process.critical,
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
    text = json_document(manifest(robot, context))
    return {"manifest.json": template("manifest.json.j2", manifest_json=text)}
