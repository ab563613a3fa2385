"""E143 unknown-host: a node, a service or the Discovery Server names a host no `host { }` block declares.

What it checks:
    Every `host:` of a node, of `dashboard { }`, `foxglove { }` and `simulation { }`, and
    `discovery { server_host }` and `control { host }` name a declared host. A `host:` in a description without any
    `host { }` block is an error too.

Why it matters:
    The build writes one output per declared host; a process placed on an undeclared one would be
    in no output, and would silently never run.

Example:
    robot_config {
      host { name: "arm" address: "10.0.0.2" }
      node { type: INFERENCE host: "gpu" ... }   # error: host "gpu" is not declared (hosts: arm)
    }
"""

import ipaddress

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import SERVICE_BLOCKS, host_names
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E143"
NAME = "unknown-host"
SEVERITY = ERROR
STAGE = "check"


def _looks_like_address(value: str) -> bool:
    try:
        ipaddress.ip_address(value)
    except ValueError:
        return value == "localhost"
    return True


def _problem(value: str, declared: list[str], what: str) -> str:
    if not declared:
        known = "the description declares no `host { }` block"
    else:
        known = f"hosts: {', '.join(declared)}"
    return f'{what} names host "{value}", which is not declared ({known})'


def check(ctx):
    declared = host_names(ctx.config)
    for view in ctx.nodes:
        if view.node.host and view.node.host not in declared:
            yield Finding(view.at("host"), _problem(view.node.host, declared, f'node "{view.name}"'))
    for block in SERVICE_BLOCKS:
        value = getattr(ctx.config, block).host
        if ctx.config.HasField(block) and value and value not in declared:
            message = _problem(value, declared, f"`{block} {{ }}`")
            if block == "foxglove" and _looks_like_address(value):
                message += "; the address the bridge listens on is foxglove's `bind`"
            yield Finding(ROBOT + (block, "host"), message)
    server = ctx.config.discovery.server_host
    if ctx.config.HasField("discovery") and server and server not in declared:
        yield Finding(ROBOT + ("discovery", "server_host"), _problem(server, declared, "`discovery { }`"))
    router = ctx.config.control.host
    if ctx.config.HasField("control") and router and router not in declared:
        yield Finding(ROBOT + ("control", "host"), _problem(router, declared, "`control { }`"))
