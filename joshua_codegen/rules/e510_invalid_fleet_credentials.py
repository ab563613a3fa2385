"""E510 invalid-fleet-credentials: dashboard credentials for the fleet view that cannot work as written.

What it checks:
    `zenoh_password_file`, `zenoh_tls_ca`, `zenoh_tls_certificate` and `zenoh_tls_private_key` are
    absolute paths and come with a `zenoh_connect`; the `zenoh_tls_*` files come with a `tls/HOST:PORT`
    endpoint, which in turn needs `zenoh_tls_ca`; a certificate comes with its key and the other way round.

Why it matters:
    The dashboard reads these files on the robot when it starts, from a working directory the build
    does not know, and Zenoh would refuse the link or silently connect without the credential: the
    robot would never appear in the fleet view, which admits only robots it knows. The build holds
    the paths only, never the password or key.

Example:
    robot_config {
      dashboard {
        zenoh_connect: "tls/10.0.0.5:7447"          # error: zenoh_connect "tls/10.0.0.5:7447" needs zenoh_tls_ca ...
        zenoh_password_file: "fleet-password"       # error: zenoh_password_file "fleet-password" is not an absolute path ...
        zenoh_tls_certificate: "/etc/joshua/arm.pem"  # error: zenoh_tls_certificate needs zenoh_tls_private_key ...
      }
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.dashboard import FLEET_CREDENTIAL_FIELDS, fleet_credential_problems

CODE = "E510"
NAME = "invalid-fleet-credentials"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    dashboard = ctx.config.dashboard
    credentials = {field: getattr(dashboard, field) for field in FLEET_CREDENTIAL_FIELDS}
    for field, problem in fleet_credential_problems(dashboard.zenoh_connect, credentials):
        yield Finding(ROBOT + ("dashboard", field), problem)
