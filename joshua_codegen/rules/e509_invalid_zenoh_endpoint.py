"""E509 invalid-zenoh-endpoint: a dashboard zenoh_connect that is not PROTOCOL/HOST:PORT.

What it checks:
    `dashboard { zenoh_connect }`, when set, reads `tcp/HOST:PORT` (or udp, tls, quic) with a
    port from 1 to 65535.

Why it matters:
    Zenoh would refuse the endpoint when the dashboard starts, and the robot would never appear
    in the fleet view; a missing protocol (`127.0.0.1:7447`) is the usual slip.

Example:
    robot_config {
      dashboard {
        zenoh_connect: "10.0.0.5:7447"   # error: zenoh endpoint "10.0.0.5:7447" is not PROTOCOL/HOST:PORT ...
      }
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.dashboard import zenoh_endpoint_problem

CODE = "E509"
NAME = "invalid-zenoh-endpoint"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    endpoint = ctx.config.dashboard.zenoh_connect
    problem = zenoh_endpoint_problem(endpoint) if endpoint else None
    if problem:
        yield Finding(ROBOT + ("dashboard", "zenoh_connect"), problem)
