"""E146 invalid-control: a `control { }` block that cannot join the hosts as written.

What it checks:
    `control { }` comes with `host { }` blocks; its port, when set, is from 1 to 65535; it names
    credentials: `password_file` with `users_file`, or `tls_ca`, `tls_certificate` and
    `tls_private_key` together (or both kinds), each an absolute path.

Why it matters:
    The hosts' agents carry control of every process over the network: without credentials any
    machine that reaches the router's port could stop the robot's nodes. Each agent reads the files
    on its own host when it starts, from a working directory the build does not know; the build
    holds the paths only, never a password or key.

Example:
    robot_config {
      host { name: "arm" address: "10.0.0.2" }
      host { name: "gpu" address: "10.0.0.3" }
      control { password_file: "control.password" }   # error: password_file needs users_file ...
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import has_hosts
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.control_plane import CREDENTIAL_FIELDS, credential_problems

CODE = "E146"
NAME = "invalid-control"
SEVERITY = ERROR
STAGE = "check"
MAX_PORT = 65535
CONTROL = ROBOT + ("control",)


def check(ctx):
    if not ctx.config.HasField("control"):
        return
    block = ctx.config.control
    if not has_hosts(ctx.config):
        yield Finding(
            CONTROL,
            "`control { }` joins the hosts of a robot on several computers, and the description declares no "
            "`host { }` (one computer is controlled through its own control socket)",
        )
        return
    if block.HasField("port") and not 0 < block.port <= MAX_PORT:
        yield Finding(CONTROL + ("port",), f"control port {block.port} is out of range 1-{MAX_PORT}")
    credentials = {field: getattr(block, field) for field in CREDENTIAL_FIELDS}
    for field, problem in credential_problems(credentials):
        yield Finding(CONTROL + ((field,) if field else ()), problem)
