"""C++ nodes receive every setting with its declared type, as rcl itself parses `-p name:=value`."""

import json
import subprocess
import sys

from joshua_codegen.check import check_text
from joshua_codegen.escape import ros_parameter
from joshua_codegen.plan import plan
from joshua_core.node_types import NODE_TYPES

# Strings that a YAML parser reads as something else when written bare.
TRICKY = [
    "yes",
    "-1",
    "1e3",
    "null",
    "~",
    "true",
    "[1]",
    "{a: 1}",
    "0x10",
    ".inf",
    "it's",
    "'quoted'",
    " lead",
    "a: b",
    "#hash",
    "- item",
    "*ref",
    "&anchor",
    "!tag",
    "%x",
    "@x",
    "`x",
    "|",
    ">",
    "a:=b",
    "caméra ‮",
    "\\",
    '"',
]

# Reads argv lists (JSON on stdin), parses each with rcl in its own context, prints each parameter's type and value.
PROBE = """
import json, sys
import rclpy
from rclpy.context import Context
from rclpy.node import Node
results = []
for index, argv in enumerate(json.load(sys.stdin)):
    context = Context()
    rclpy.init(args=argv, context=context)
    node = Node(f"probe_{index}", context=context, automatically_declare_parameters_from_overrides=True)
    results.append({name: [p.type_.name, p.value] for name, p in node._parameters.items()})
    node.destroy_node()
    rclpy.shutdown(context=context)
json.dump(results, sys.stdout)
"""
ROS_TYPES = {bool: "BOOL", int: "INTEGER", float: "DOUBLE", str: "STRING"}


def parsed_by_rcl(argvs: list[list[str]], env: dict) -> list[dict]:
    result = subprocess.run(
        [sys.executable, "-c", PROBE], input=json.dumps(argvs), capture_output=True, text=True, env=env, timeout=120
    )
    assert result.returncode == 0, result.stderr[-3000:]
    return json.loads(result.stdout)


def declared_type(value) -> str:
    if isinstance(value, list):
        return ROS_TYPES[type(value[0])] + "_ARRAY"
    return ROS_TYPES[type(value)]


def description(values: list[str]) -> str:
    nodes = "".join(
        f"""
  node {{
    name: "encoder{index}"
    type: ENCODER_PUBLISHER
    preferred_backend: CPP
    topic_name: "/arm{index}/joint_states"
    serial_port: {json.dumps(value if index % 2 else "/dev/ttyUSB" + str(index))}
    device_ids: [1, 2, 3, 4, 5, 6]
    frame_id: {json.dumps(value)}
  }}"""
        for index, value in enumerate(values)
    )
    return f'robot_config {{\n  name: "probe"\n  mode: MODE_TELEOPERATION{nodes}\n}}\n'


def test_every_setting_of_a_cpp_node_arrives_in_rcl_with_its_declared_type_and_value(ros_env):
    result = check_text("probe.pbtxt", description(TRICKY))
    assert not result.has_errors, [d.message for d in result.diagnostics if d.is_error]
    robot = plan(result.description, "probe.pbtxt")
    processes = [p for p in robot.processes if p.cpp_args]
    assert len(processes) == len(TRICKY)
    received = parsed_by_rcl([list(p.cpp_args) for p in processes], ros_env)
    nodes = {node.name: node for node in robot.nodes}
    for process, parameters in zip(processes, received):
        settings = nodes[process.name].settings
        expected = {
            "frame_id": settings.frame_id,
            "serial_port": settings.serial_port,
            "device_ids": list(settings.device_ids),
            "joint_names": list(settings.joint_names),
            "baud_rate": settings.baud_rate,
            "rate_hz": settings.rate_hz,
            "topic_name": settings.topic.name,
            "qos_depth": settings.qos.depth,
        }
        for name, value in expected.items():
            assert name in NODE_TYPES["ENCODER_PUBLISHER"].cpp_parameters
            assert parameters[name] == [declared_type(value), value], (process.name, name)


def test_plain_values_keep_their_types_too(ros_env):
    values = [0, -7, 2**40, 0.5, 1e-05, 1e20, 100.0, True, False, float("inf"), [1, 2], [0.5, 2.0], ["a", "b: c"]]
    argv = ["--ros-args"] + [
        arg for index, value in enumerate(values) for arg in ("-p", f"v{index}:={ros_parameter(value)}")
    ]
    parameters = parsed_by_rcl([argv], ros_env)[0]
    for index, value in enumerate(values):
        assert parameters[f"v{index}"] == [declared_type(value), value], index
