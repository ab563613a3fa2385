"""E145 invalid-discovery: a `discovery { }` block without its server host, or with a port out of range.

What it checks:
    `discovery { server_host }` is set, and `discovery { port }`, when set, is from 1 to 65535.

Why it matters:
    Every process of every host is generated to find the others through this server; without a
    host to run it on, or on a port it cannot listen on, no process would find any other.

Example:
    robot_config {
      host { name: "arm" address: "10.0.0.2" }
      discovery { port: 11811 }   # error: discovery { } needs server_host
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E145"
NAME = "invalid-discovery"
SEVERITY = ERROR
STAGE = "check"
MAX_PORT = 65535
DISCOVERY = ROBOT + ("discovery",)


def check(ctx):
    if not ctx.config.HasField("discovery"):
        return
    block = ctx.config.discovery
    if not block.server_host:
        yield Finding(DISCOVERY, "`discovery { }` needs server_host: the host that runs the Discovery Server")
    if block.HasField("port") and not 0 < block.port <= MAX_PORT:
        yield Finding(DISCOVERY + ("port",), f"discovery port {block.port} is out of range 1-{MAX_PORT}")
