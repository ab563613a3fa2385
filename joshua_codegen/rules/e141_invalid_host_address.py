"""E141 invalid-host-address: a `host { }` block without an address the others can reach.

What it checks:
    Each `host { address }` is set and is an IPv4 address other than 0.0.0.0 or a multicast one.

Why it matters:
    The address is where the other hosts find this one: the Discovery Server's locator in every
    process's DDS profile, and what the manifest tells each host's supervisor about the others. A
    name such as "arm.local" would depend on name resolution working on every computer at start-up.

Example:
    robot_config {
      host { name: "arm" address: "arm.local" }   # error: address "arm.local" is not an IPv4 address
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import address_problem
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E141"
NAME = "invalid-host-address"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for index, host in enumerate(ctx.config.host):
        problem = address_problem(host.address)
        if problem:
            at = ROBOT + ("host", index) + (("address",) if host.address else ())
            yield Finding(at, problem)
