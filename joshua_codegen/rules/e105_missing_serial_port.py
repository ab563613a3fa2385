"""E105 missing-serial-port: a node that talks to a device over a serial line has no serial_port.

What it checks:
    {serial_types} set `serial_port` (e.g. /dev/ttyUSB0). Not checked in MODE_SIMULATION, where these
    nodes are replaced by the simulation and open no device; MOCK_* nodes never need one.

Why it matters:
    These nodes talk to hardware over a serial line; there is no port they could safely guess.

Example:
    node {
      type: ENCODER_PUBLISHER      # error: ENCODER_PUBLISHER node "encoder_publisher" has no serial_port
      topic_name: "/leader/joint_states"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

TYPE_LISTS = {"serial_types": lambda entry: "serial_port" in entry.required}
CODE = "E105"
NAME = "missing-serial-port"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    if ctx.config.mode == pb.MODE_SIMULATION:
        return
    for view in ctx.lacking("serial_port"):
        yield Finding(view.path, f'{view.label} has no serial_port (e.g. serial_port: "/dev/ttyUSB0")')
