"""Facts of the control plane of a robot on several hosts that the compiler and the runtime agree on: the
`host_agent` process, its Zenoh keys and endpoint, the credentials of `control { }` and the local socket
through which `supervisor.py ctl` and the dashboard reach the other hosts.

Every host H runs an agent, the process `host_agent_H`. The one on the control host is a Zenoh router listening on that host's
address; the others connect to it as clients. Each agent publishes its host's status under
`joshua/<robot>/hosts/<host>/status` and answers control requests for its host's supervisor as the
queryable `joshua/<robot>/hosts/<host>/control`.
"""

PROCESS_PREFIX = "host_agent_"  # host H runs the process host_agent_H (a reserved node name)
PROCESS_TYPE = "HOST_AGENT"
RUNTIME_MODULE = "joshua_runtime.hosts.agent"
DEFAULT_PORT = 7448  # one above the fleet view's 7447
KEY_ROOT = "joshua"
# Set by a host's supervisor for its processes: where its host_agent serves the local socket that reaches the
# other hosts (`supervisor.py ctl --host NAME`, the dashboard).
HOSTS_SOCKET_VARIABLE = "JOSHUA_HOSTS_SOCKET"
# The `control { }` fields naming credentials, each a path on the hosts; the agent takes each as `--FIELD`
# with dashes (see credential_flag) and reads the files itself.
CREDENTIAL_FIELDS = ("password_file", "users_file", "tls_ca", "tls_certificate", "tls_private_key")
PASSWORD_FIELDS = ("password_file", "users_file")
TLS_FIELDS = ("tls_ca", "tls_certificate", "tls_private_key")


def process_name(host: str) -> str:
    """The name of `host`'s agent: unique in the whole robot, so the dashboard's routes name it alone."""
    return f"{PROCESS_PREFIX}{host}"


def hosts_socket_path(control_socket: str) -> str:
    """The agent's local socket beside a host's control socket: `split.arm.hosts.sock` for `split.arm.sock` (as
    supervisor.py's ctl_hosts.py, which cannot import this, derives it too)."""
    return control_socket.removesuffix(".sock") + ".hosts.sock"


def hosts_key(robot: str) -> str:
    return f"{KEY_ROOT}/{robot}/hosts"


def status_key(robot: str, host: str) -> str:
    """Where `host`'s agent publishes its supervisor's status."""
    return f"{hosts_key(robot)}/{host}/status"


def control_key(robot: str, host: str) -> str:
    """The queryable through which `host`'s supervisor takes control requests."""
    return f"{hosts_key(robot)}/{host}/control"


def uses_tls(credentials: dict[str, str]) -> bool:
    return any(credentials.get(field) for field in TLS_FIELDS)


def endpoint(address: str, port: int, tls: bool) -> str:
    """The router's Zenoh endpoint: `tcp/10.0.0.2:7448`, or `tls/...` when the hosts hold certificates."""
    return f"{'tls' if tls else 'tcp'}/{address}:{port}"


def credential_flag(field: str) -> str:
    """The agent's option for a credential field: `tls_ca` -> `--tls-ca`."""
    return "--" + field.replace("_", "-")


def credential_problems(credentials: dict[str, str], router: bool = True) -> list[tuple[str, str]]:
    """(field, why) for every problem of the credentials (field -> path) of `control { }`, or of one agent's
    (`router`: the one that listens, which alone has the dictionary): none at all, a password without the
    dictionary (or the other way round), TLS without all three files, relative paths."""
    given = {field for field, path in credentials.items() if path}
    problems = []
    if not router:
        if "users_file" in given:
            problems.append(("users_file", "users_file is for the router's host only (the agent that listens)"))
        given |= {"users_file"} if "password_file" in given else set()
    if not given:
        problems.append(
            (
                "",
                "`control { }` needs credentials: password_file and users_file, or tls_ca, tls_certificate and "
                "tls_private_key (every host authenticates as itself)",
            )
        )
    for field, other in (PASSWORD_FIELDS, PASSWORD_FIELDS[::-1]):
        if field in given and other not in given:
            problems.append((field, f"{field} needs {other}: each host's password, and the router's dictionary"))
    tls_given = [field for field in TLS_FIELDS if field in given]
    missing = [field for field in TLS_FIELDS if field not in given]
    if tls_given and missing:
        problems.append(
            (
                tls_given[0],
                f"mutual TLS needs tls_ca, tls_certificate and tls_private_key together (missing: {', '.join(missing)})",
            )
        )
    for field in CREDENTIAL_FIELDS:
        path = credentials.get(field, "")
        if path and not path.startswith("/"):
            problems.append((field, f'{field} "{path}" is not an absolute path (each host_agent reads it on its host)'))
    return problems
