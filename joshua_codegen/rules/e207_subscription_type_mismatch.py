"""E207 subscription-type-mismatch: a subscriber expects a type that no publisher of its topic sends.

What it checks:
    A subscriber of `topic_name` ({subscriber_types}) uses a type that at least one publisher of that
    topic publishes. A recorder's topic_name is recorded as the JointState action.

Why it matters:
    A subscription of another type never matches the publishers: no data flows, silently.

Example:
    node { type: CAMERA_PUBLISHER topic_name: "/arm/commands" }
    node { type: ACTUATOR_SUBSCRIBER topic_name: "/arm/commands" ... }   # error: expects JointState
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.node_families import TopicRole

TYPE_LISTS = {"subscriber_types": lambda entry: entry.topic == TopicRole.SUBSCRIBES}
CODE = "E207"
NAME = "subscription-type-mismatch"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for topic, subscribers in ctx.subscribers.items():
        publishers = [p for p in ctx.publishers.get(topic, ()) if p.message_type]
        if not publishers:
            continue
        published = {p.message_type for p in publishers}
        for sub in subscribers:
            if sub.message_type and sub.message_type not in published:
                path = sub.at[:-1] + ("message_type",)
                where = path if ctx.written(path) else sub.at
                yield Finding(
                    where,
                    f'node "{sub.view.name}" subscribes to "{topic}" as {sub.message_type}, '
                    f"but it is published as {publishers[0].message_type}",
                    ((publishers[0].at, f'publisher "{publishers[0].view.name}" declared here'),),
                )
