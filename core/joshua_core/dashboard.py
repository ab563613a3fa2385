"""Facts of the web dashboard both sides agree on: its process name, defaults, what a bind address and a
zenoh endpoint look like, and the credentials it gives the fleet view."""

import ipaddress
import re

PROCESS_NAME = "dashboard"
PROCESS_TYPE = "DASHBOARD"
RUNTIME_EXTRA = "dashboard"  # the extra of joshua-runtime the dashboard process needs installed
DEFAULT_PORT = 8640
DEFAULT_BIND = "127.0.0.1"
LOOPBACK_NAMES = ("localhost",)
WILDCARD_BINDS = ("0.0.0.0", "::")  # every address of the machine
ZENOH_ENDPOINT_EXAMPLE = "tcp/127.0.0.1:7447"
MAX_HOST_NAME_CHARS = 253
_HOST_LABEL = re.compile(r"^(?!-)[A-Za-z0-9-]{1,63}(?<!-)$")
_ZENOH_ENDPOINT = re.compile(r"^(tcp|udp|tls|quic)/(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9.-]+):(\d{1,5})$")
# Protocols whose links Zenoh secures with TLS (transport/link/tls settings).
TLS_PROTOCOLS = ("tls", "quic")
# The `dashboard` fields naming the robot's credentials towards the fleet view, each a path on the robot;
# the dashboard takes each as `--zenoh-...` (see credential_flag) and reads the files itself.
FLEET_CREDENTIAL_FIELDS = ("zenoh_password_file", "zenoh_tls_ca", "zenoh_tls_certificate", "zenoh_tls_private_key")
_TLS_FIELDS = ("zenoh_tls_ca", "zenoh_tls_certificate", "zenoh_tls_private_key")
_KEY_PAIR = ("zenoh_tls_certificate", "zenoh_tls_private_key")


def bind_problem(bind: str) -> str | None:
    """Why `bind` is not an address to listen on (an IP address or localhost), or None."""
    if bind in LOOPBACK_NAMES:
        return None
    try:
        ipaddress.ip_address(bind)
    except ValueError:
        return f'bind "{bind}" is not an IP address (e.g. 127.0.0.1, 0.0.0.0, ::1) or localhost'
    return None


def is_loopback(bind: str) -> bool:
    """True for 127.0.0.0/8, ::1 and localhost: only this machine can connect."""
    if bind in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(bind).is_loopback
    except ValueError:
        return False


def allowed_host_problem(name: str) -> str | None:
    """Why `name` is not a host name (`robot.example.org`) or IP address the page may be reached by, or None."""
    try:
        ipaddress.ip_address(name)
        return None
    except ValueError:
        pass
    labels = name.removesuffix(".").split(".")
    if len(name) > MAX_HOST_NAME_CHARS or not all(_HOST_LABEL.match(label) for label in labels):
        return (
            f'allowed_host "{name}" is not a host name (letters, digits and hyphens, dot-separated, '
            "e.g. robot.example.org) or an IP address; give it without scheme or port"
        )
    return None


def zenoh_endpoint_problem(endpoint: str) -> str | None:
    """Why `endpoint` is not a zenoh endpoint PROTOCOL/HOST:PORT with a port from 1 to 65535, or None."""
    match = _ZENOH_ENDPOINT.match(endpoint)
    if match is None or not 0 < int(match.group(3)) < 65536:
        return f'zenoh endpoint "{endpoint}" is not PROTOCOL/HOST:PORT with a port from 1 to 65535 (e.g. {ZENOH_ENDPOINT_EXAMPLE})'
    return None


def endpoint_protocol(endpoint: str) -> str:
    """`tls` of `tls/10.0.0.5:7447`."""
    return endpoint.partition("/")[0]


def endpoint_host(endpoint: str) -> str:
    """`10.0.0.5` of `tls/10.0.0.5:7447`, `::1` of `tcp/[::1]:7447`."""
    return endpoint.partition("/")[2].rpartition(":")[0].strip("[]")


def credential_flag(field: str) -> str:
    """The dashboard's option for a credential field: `zenoh_tls_ca` -> `--zenoh-tls-ca`."""
    return "--" + field.replace("_", "-")


def fleet_credential_problems(endpoint: str, credentials: dict[str, str]) -> list[tuple[str, str]]:
    """(field, why) for every problem of the credentials (field -> path) a dashboard gives the fleet view at
    `endpoint` (empty: no fleet)."""
    problems = []
    given = {field: path for field, path in credentials.items() if path}
    tls = endpoint_protocol(endpoint) in TLS_PROTOCOLS
    for field, path in given.items():
        if not endpoint:
            problems.append((field, f"{field} needs zenoh_connect, the fleet view it is a credential for"))
        elif field in _TLS_FIELDS and not tls:
            problems.append((field, f'{field} needs a tls/HOST:PORT zenoh_connect, not "{endpoint}"'))
        if not path.startswith("/"):
            problems.append((field, f'{field} "{path}" is not an absolute path (the dashboard reads it on the robot)'))
    if endpoint and tls and "zenoh_tls_ca" not in given:
        problems.append(
            (
                "zenoh_connect",
                f'zenoh_connect "{endpoint}" needs zenoh_tls_ca, the CA that signed the fleet\'s certificate',
            )
        )
    for field, other in (_KEY_PAIR, _KEY_PAIR[::-1]):
        if field in given and other not in given:
            problems.append((field, f"{field} needs {other}: mutual TLS takes a certificate and its key"))
    return problems


def page_url(bind: str, port: int) -> str:
    """The address of the dashboard's page: the bind address, or this machine's name when bound to all."""
    import socket

    host = socket.gethostname() if bind in WILDCARD_BINDS else bind
    return f"http://{f'[{host}]' if ':' in host else host}:{port}/"
