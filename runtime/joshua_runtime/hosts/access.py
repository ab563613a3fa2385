"""Who may join a robot's control plane, in Zenoh's terms: each host authenticates as itself (user name, or
certificate common name, = the host's name) and an access control list on the router lets host H

- publish only its own status (`put` on `joshua/<robot>/hosts/H/status`),
- serve only its own control queryable (declare it, and reply, on `joshua/<robot>/hosts/H/control`),
- follow every host's status and send control requests to every host (the owner's dashboard and `ctl` run on
  any host, with that host's credentials);

everything else is denied, for every other peer too: a peer without the robot's credentials cannot open a
session at all. Secrets stay in their files: the password is read into the session's settings, the TLS
files and the router's dictionary are handed to Zenoh by path.
"""

from dataclasses import dataclass

from joshua_core import control_plane
from joshua_runtime.dashboard.zenoh_link import read_password, readable
from joshua_runtime.errors import SettingsError

# Zenoh reassembles a message up to this size (default 1 GiB): a `logs` reply holds at most 1 MiB of a node's
# output, which JSON may double.
MAX_MESSAGE_BYTES = 4 * 1024 * 1024
# How long a host's agent waits for the router at a time before it tries again (a client opens only once the
# router answers; the agent serves its own host meanwhile).
CONNECT_TIMEOUT_MS = 2000


@dataclass(frozen=True)
class Credentials:
    """The `control { }` credential paths one agent was given (empty: not given)."""

    password_file: str = ""
    users_file: str = ""
    tls_ca: str = ""
    tls_certificate: str = ""
    tls_private_key: str = ""

    @classmethod
    def from_arguments(cls, args) -> "Credentials":
        return cls(*(getattr(args, field) or "" for field in control_plane.CREDENTIAL_FIELDS))

    def as_dict(self) -> dict[str, str]:
        return {field: getattr(self, field) for field in control_plane.CREDENTIAL_FIELDS}


def _tls(credentials: Credentials, side: str) -> dict:
    """TLS settings for `side` (listen, connect): this host's certificate, the hosts' CA, mutual."""
    return {
        "transport/link/tls/root_ca_certificate": readable("tls_ca", credentials.tls_ca),
        f"transport/link/tls/{side}_certificate": readable("tls_certificate", credentials.tls_certificate),
        f"transport/link/tls/{side}_private_key": readable("tls_private_key", credentials.tls_private_key),
        "transport/link/tls/enable_mtls": True,
    }


def check(credentials: Credentials, router: bool) -> None:
    """Refuse credentials that cannot work, as E146 does at build time (only the router has the dictionary)."""
    problems = control_plane.credential_problems(credentials.as_dict(), router)
    if problems:
        raise SettingsError(problems[0][1])


def router_settings(robot: str, hosts: tuple[str, ...], credentials: Credentials) -> dict:
    """The settings of the agent that listens: the hosts' dictionary and TLS files, and the access control list."""
    check(credentials, router=True)
    settings: dict = {"transport/link/rx/max_message_size": MAX_MESSAGE_BYTES}
    if credentials.users_file:
        settings["transport/auth/usrpwd/dictionary_file"] = readable("users_file", credentials.users_file)
    if credentials.tls_certificate:
        settings |= _tls(credentials, "listen")
        settings["transport/link/tls/close_link_on_expiration"] = True
    settings["access_control"] = access_control(
        robot, hosts, by_user=bool(credentials.users_file), by_certificate=bool(credentials.tls_certificate)
    )
    return settings


def client_settings(host: str, credentials: Credentials) -> dict:
    """The settings of an agent that connects: its host's password (user: the host's name) and certificate."""
    check(credentials, router=False)
    settings: dict = {
        "transport/link/rx/max_message_size": MAX_MESSAGE_BYTES,
        "connect/timeout_ms": CONNECT_TIMEOUT_MS,
    }
    if credentials.password_file:
        settings["transport/auth/usrpwd/user"] = host
        settings["transport/auth/usrpwd/password"] = read_password(credentials.password_file)
    if credentials.tls_certificate:
        settings |= _tls(credentials, "connect")
    return settings


def access_control(robot: str, hosts: tuple[str, ...], by_user: bool, by_certificate: bool) -> dict:
    """Zenoh's ACL on the router (rules above); a subject matches host H by user name and/or certificate."""
    every_status = control_plane.status_key(robot, "*")
    every_control = control_plane.control_key(robot, "*")
    rules, subjects, policies = [], [], []
    for host in hosts:
        own = [control_plane.status_key(robot, host), control_plane.control_key(robot, host)]
        host_rules = [
            _rule(f"{host}-own", ["put", "declare_queryable", "reply"], "ingress", own),
            _rule(f"{host}-ask", ["declare_subscriber", "query"], "ingress", [every_status, every_control]),
            _rule(f"{host}-hear", ["put", "reply"], "egress", [every_status, every_control]),
            _rule(f"{host}-serve", ["query"], "egress", [control_plane.control_key(robot, host)]),
        ]
        rules += host_rules
        subject = {"id": host}
        if by_user:
            subject["usernames"] = [host]
        if by_certificate:
            subject["cert_common_names"] = [host]
        subjects.append(subject)
        policies.append({"rules": [rule["id"] for rule in host_rules], "subjects": [host]})
    return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects, "policies": policies}


def _rule(rule_id: str, messages: list[str], flow: str, keys: list[str]) -> dict:
    return {"id": rule_id, "messages": messages, "flows": [flow], "permission": "allow", "key_exprs": keys}
