"""E401 serial-port-conflict: two nodes claim the same serial port.

What it checks:
    Each `serial_port` of a node that opens it ({serial_types}) is used by one node only. MOCK_*
    nodes open no port and are not counted. The error is at the second node, with the first as a note.
    With `host { }` blocks a port belongs to its node's host: nodes on different hosts may both
    use /dev/ttyUSB0.

Why it matters:
    Two processes on one serial line interleave their bytes: both read garbage and servos may
    receive corrupted commands.

Example:
    node { type: ENCODER_PUBLISHER serial_port: "/dev/ttyUSB0" ... }
    node { type: ACTUATOR_SUBSCRIBER serial_port: "/dev/ttyUSB0" ... }  # error: already claimed
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import node_host
from joshua_codegen.rules.context import Finding

TYPE_LISTS = {"serial_types": lambda entry: "serial_port" in entry.claims}
CODE = "E401"
NAME = "serial-port-conflict"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    owners = {}
    for view in ctx.typed_nodes:
        port = view.node.serial_port
        if view.node.type not in defaults.SERIAL or not port:
            continue
        host = node_host(ctx.config, view.node)
        first = owners.setdefault((host, port), view)
        if first is not view:
            on = f' of host "{host}"' if host else ""
            yield Finding(
                view.at("serial_port"),
                f'serial port "{port}"{on} is already claimed by node "{first.name}"',
                ((first.at("serial_port"), "claimed here"),),
            )
