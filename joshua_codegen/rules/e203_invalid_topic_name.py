"""E203 invalid-topic-name: a topic name that breaks the ROS 2 naming rules.

What it checks:
    `topic_name`, `state_topic`, `odom_topic`, every `input_topics` entry and the topic_name of every
    topic a CUSTOM node declares (`publishes`, `subscribes`) is an absolute (`/a/b`), relative
    (`a/b`) or private (`~/a`) ROS 2 name: letters, digits, "_" and "/" only, no "//", no trailing
    "/", no part starting with a digit, "~" only as the first character and followed by "/",
    no substitutions (`{node}`), at most 247 characters once resolved. Nodes have no namespace,
    so `a/b` means `/a/b` and `~/a` means `/<node name>/a`.

Why it matters:
    rclpy refuses such names when the node starts, so the robot would fail at launch.

Example:
    node {
      topic_name: "/camera//image raw"    # error: topic name "/camera//image raw" is invalid: it contains " "
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.ros_names import topic_problem
from joshua_codegen.rules.context import Finding

CODE = "E203"
NAME = "invalid-topic-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        node = view.node
        named = []
        if node.topic_name:
            named.append((view.at("topic_name"), node.topic_name))
        if node.state_topic:
            named.append((view.at("state_topic"), node.state_topic))
        if node.odom_topic:
            named.append((view.at("odom_topic"), node.odom_topic))
        named.extend((view.at("input_topics", k), name) for k, name in enumerate(node.input_topics))
        if defaults.entry(node).declares_topics:
            for field in ("publishes", "subscribes"):
                named.extend(
                    (view.at(field, k, "topic_name"), topic.topic_name)
                    for k, topic in enumerate(getattr(node, field))
                    if topic.topic_name
                )
        for path, name in named:
            problem = topic_problem(name, view.name)
            if problem is not None:
                yield Finding(path, f'topic name "{name}" is invalid: {problem}')
