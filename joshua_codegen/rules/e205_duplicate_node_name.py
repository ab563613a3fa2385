"""E205 duplicate-node-name: two nodes end up with the same name.

What it checks:
    Node names, written or derived (an unnamed node is named after its type in lower case,
    suffixed _1, _2 ... when several share the type), are unique. In MODE_SIMULATION the name
    "simulation" is reserved for the simulation engine, with a `dashboard { }` block the name
    "dashboard" is reserved for the dashboard process, with a `discovery { }` block the name
    "discovery_server" for the Discovery Server, and with `host { }` blocks the name "host_agent_H"
    for the agent of host H. The error is at the second node, with the first as
    a note.

Why it matters:
    Two ROS 2 nodes with one name confuse tools and parameters, and the name is also the node's
    entrypoint file and systemd unit: one would overwrite the other.

Example:
    node { name: "camera_publisher" type: CAMERA_PUBLISHER topic_name: "/a" }
    node { type: CAMERA_PUBLISHER topic_name: "/b" }    # error: derived name "camera_publisher" is taken
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core import control_plane, discovery
from joshua_core.dashboard import PROCESS_NAME as DASHBOARD_NAME
from joshua_core.schema import robot_config_pb2 as pb

CODE = "E205"
NAME = "duplicate-node-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    first_by_name = {}
    for view in ctx.nodes:
        first = first_by_name.setdefault(view.name, view)
        derived = "" if view.node.name else " (derived from its type; set name: to tell the nodes apart)"
        if first is not view:
            yield Finding(
                view.at("name"),
                f'node name "{view.name}" is already used{derived}',
                ((first.at("name"), f'node "{view.name}" first named here'),),
            )
        elif ctx.config.mode == pb.MODE_SIMULATION and view.name == defaults.SIMULATION_NAME:
            yield Finding(
                view.at("name"),
                f'node name "{view.name}" is reserved for the simulation engine in MODE_SIMULATION{derived}',
            )
        elif ctx.config.HasField("dashboard") and view.name == DASHBOARD_NAME:
            yield Finding(view.at("name"), f'node name "{view.name}" is reserved for the dashboard process{derived}')
        elif view.name in {control_plane.process_name(host.name) for host in ctx.config.host}:
            yield Finding(
                view.at("name"),
                f'node name "{view.name}" is reserved for the agent of host "{view.name.removeprefix(control_plane.PROCESS_PREFIX)}"{derived}',
            )
        elif ctx.config.HasField("discovery") and view.name == discovery.PROCESS_NAME:
            yield Finding(
                view.at("name"), f'node name "{view.name}" is reserved for the Discovery Server process{derived}'
            )
