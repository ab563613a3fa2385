"""W201 multiple-actuator-publishers: an actuator's command topic has more than one publisher.

What it checks:
    The topic an ACTUATOR_SUBSCRIBER (or its mock) subscribes to is published by at most one node
    of the description.

Why it matters:
    Two sources of joint commands (say a leader arm and a policy) make the arm jump between them.

Example:
    node { type: ENCODER_PUBLISHER topic_name: "/arm/commands" ... }
    node { type: INFERENCE topic_name: "/arm/commands" ... }
    node { type: ACTUATOR_SUBSCRIBER topic_name: "/arm/commands" ... }   # warning: 2 publishers
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding

CODE = "W201"
NAME = "multiple-actuator-publishers"
SEVERITY = WARNING
STAGE = "check"
# Publishers named in the message and notes; the rest are counted.
NAMED_PUBLISHERS = 2


def check(ctx):
    for topic, subscribers in ctx.subscribers.items():
        publishers = ctx.publishers.get(topic, [])
        if len(publishers) < 2:
            continue
        named = publishers[:NAMED_PUBLISHERS]
        names = ", ".join(f'"{p.view.name}"' for p in named)
        more = len(publishers) - len(named)
        listing = names + (f" and {more} more" if more else "")
        related = tuple((p.at, "publisher declared here") for p in named)
        for sub in subscribers:
            if sub.view.node.type in defaults.ACTUATORS:
                yield Finding(
                    sub.at,
                    f'actuator "{sub.view.name}" receives commands on "{topic}" from '
                    f"{len(publishers)} publishers: {listing}",
                    related,
                )
