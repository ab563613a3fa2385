"""E508 invalid-dashboard-address: a dashboard port out of range, a bind that is no address, or an
allowed_host that is no host name.

What it checks:
    `dashboard { port }`, when set, is from 1 to 65535, `dashboard { bind }`, when set, is an
    IP address (IPv4 or IPv6) or `localhost`, and each `dashboard { allowed_host }` is a host name
    or an IP address, without scheme or port.

Why it matters:
    The dashboard process would fail at start with "cannot listen", after the rest of the robot
    came up; port 0 would pick a random port nobody can find. A host name other than localhost
    is refused too: which interfaces it resolves to decides who may reach the robot's controls.
    An allowed_host such as "http://robot:8640" would never match a Host header, so the page would
    be refused under the very name it was meant to allow.

Example:
    robot_config {
      dashboard {
        port: 70000              # error: dashboard port 70000 is out of range 1-65535
        bind: "robot.local"      # error: bind "robot.local" is not an IP address ...
        allowed_host: "http://robot:8640"   # error: allowed_host "http://robot:8640" is not a host name ...
      }
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.dashboard import allowed_host_problem, bind_problem

CODE = "E508"
NAME = "invalid-dashboard-address"
SEVERITY = ERROR
STAGE = "check"
MAX_PORT = 65535
DASHBOARD = ROBOT + ("dashboard",)


def check(ctx):
    dashboard = ctx.config.dashboard
    if dashboard.HasField("port") and not 0 < dashboard.port <= MAX_PORT:
        yield Finding(DASHBOARD + ("port",), f"dashboard port {dashboard.port} is out of range 1-{MAX_PORT}")
    problem = bind_problem(dashboard.bind) if dashboard.bind else None
    if problem:
        yield Finding(DASHBOARD + ("bind",), problem)
    for index, name in enumerate(dashboard.allowed_host):
        problem = allowed_host_problem(name)
        if problem:
            yield Finding(DASHBOARD + ("allowed_host", index), problem)
