"""E507 simulation-host-mismatch: in MODE_SIMULATION, a node the engine stands in for is placed on another host.

What it checks:
    With `host { }` blocks and MODE_SIMULATION, every node the simulation replaces ({hardware_types})
    runs on the simulation engine's host (`simulation { host }`, default the first host).

Why it matters:
    The engine publishes the replaced nodes' topics from its own process; a node placed elsewhere
    would be simulated on another computer than the one its description says, and that host's
    output would miss it.

Example:
    robot_config {
      mode: MODE_SIMULATION
      host { name: "arm" address: "10.0.0.2" }
      host { name: "gpu" address: "10.0.0.3" }
      simulation { model: "builtin:so100" host: "gpu" }
      node { type: ACTUATOR_SUBSCRIBER host: "arm" ... }   # error: simulated on "gpu"
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import has_hosts, host_names, node_host, service_host
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

TYPE_LISTS = {"hardware_types": lambda entry: entry.hardware}
CODE = "E507"
NAME = "simulation-host-mismatch"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    config = ctx.config
    if config.mode != pb.MODE_SIMULATION or not has_hosts(config):
        return
    engine = service_host(config, "simulation")
    if engine not in host_names(config):
        return  # E143
    for view in ctx.typed_nodes:
        if view.node.type not in defaults.HARDWARE:
            continue
        host = node_host(config, view.node)
        if host != engine and host in host_names(config):
            related = ((ROBOT + ("simulation", "host"), "the engine's host"),) if config.simulation.host else ()
            yield Finding(
                view.at("host"),
                f'{view.label} runs on host "{host}", but the simulation engine that stands in for it in '
                f'MODE_SIMULATION runs on host "{engine}"',
                related,
            )
