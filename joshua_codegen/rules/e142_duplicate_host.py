"""E142 duplicate-host: two `host { }` blocks with one name or one address.

What it checks:
    Host names are unique, and so are host addresses. The error is at the second block's field,
    with the first as a note.

Why it matters:
    A node placed on a name declared twice could run on either computer, and each host's output
    directory would be written twice. Two hosts at one address are one computer: its devices would
    be claimed twice without E401 noticing, and both would serve the same control socket.

Example:
    robot_config {
      host { name: "arm" address: "10.0.0.2" }
      host { name: "gpu" address: "10.0.0.2" }   # error: address "10.0.0.2" is already host "arm"'s
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding

CODE = "E142"
NAME = "duplicate-host"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    names: dict[str, int] = {}
    addresses: dict[str, int] = {}
    for index, host in enumerate(ctx.config.host):
        if host.name:
            first = names.setdefault(host.name, index)
            if first != index:
                yield Finding(
                    ROBOT + ("host", index, "name"),
                    f'host name "{host.name}" is already declared',
                    ((ROBOT + ("host", first, "name"), "first declared here"),),
                )
        if host.address:
            first = addresses.setdefault(host.address, index)
            if first != index:
                owner = ctx.config.host[first].name
                yield Finding(
                    ROBOT + ("host", index, "address"),
                    f'address "{host.address}" is already the address of host "{owner}"',
                    ((ROBOT + ("host", first, "address"), "first used here"),),
                )
