"""Who the fleet view admits over zenoh, in zenoh's own terms: user/password authentication (`--users`, a
zenoh dictionary file of `ROBOT:PASSWORD` lines), TLS (`--tls-certificate`, `--tls-private-key`; mutual
with `--tls-ca`, the CA of the robots' certificates, whose common names `--robots` lists), and an access
control list that lets each robot put and delete under `joshua/<its name>/**` (a dashboard that stops
deletes its status) and do nothing else: no other key, no subscription, no query.

Without credentials any peer that reaches the endpoint is admitted, so the fleet allows that only on a
loopback endpoint (this machine). Secrets stay in their files: zenoh gets the paths.
"""

from dataclasses import dataclass

from joshua_core.dashboard import TLS_PROTOCOLS, endpoint_host, endpoint_protocol, is_loopback
from joshua_core.names import is_robot_name
from joshua_runtime.dashboard.fleet_status import MAX_STATUS_BYTES
from joshua_runtime.dashboard.zenoh_link import KEY_ROOT
from joshua_runtime.errors import SettingsError

# Zenoh reassembles a message split in fragments up to this size (its default is 1 GiB): twice a status's limit.
MAX_ZENOH_MESSAGE_BYTES = 2 * MAX_STATUS_BYTES
ANYONE = "anyone"
PUBLISHED_MESSAGES = ["put", "delete"]  # what a robot may send under its own keys


@dataclass(frozen=True)
class FleetAccess:
    """The checked access settings of a fleet listening on `endpoint`."""

    endpoint: str
    robots: tuple[str, ...]  # the robots admitted by name; empty: anyone (loopback only)
    users_file: str = ""
    tls_certificate: str = ""
    tls_private_key: str = ""
    tls_ca: str = ""

    @classmethod
    def from_arguments(cls, args) -> "FleetAccess":
        """Check the flags against each other and read the names; SettingsError says what is wrong."""
        endpoint = args.listen
        tls_flags = {"--tls-certificate": args.tls_certificate, "--tls-private-key": args.tls_private_key}
        tls_flags["--tls-ca"] = args.tls_ca
        tls = endpoint_protocol(endpoint) in TLS_PROTOCOLS
        for flag, value in tls_flags.items():
            if value and not tls:
                raise SettingsError(f"{flag} needs --listen tls/HOST:PORT (it is {endpoint})")
        if tls and not (args.tls_certificate and args.tls_private_key):
            raise SettingsError(
                f"--listen {endpoint} needs --tls-certificate and --tls-private-key (the fleet's certificate and key)"
            )
        for flag, value in tls_flags.items():
            if value:
                _readable(flag, value)
        if args.robots and not args.tls_ca:
            raise SettingsError("--robots names the robots of --tls-ca (mutual TLS); without it, --users names them")
        if args.robots and args.users:
            raise SettingsError("give the robots' names once: with --users, its file names them")
        if args.users:
            robots = read_users(args.users)
        elif args.tls_ca:
            if not args.robots:
                raise SettingsError(
                    "--tls-ca needs --robots FILE, the robots' names (their certificates' common names)"
                )
            robots = read_robots(args.robots)
        else:
            robots = ()
            if not is_loopback(endpoint_host(endpoint)):
                raise SettingsError(
                    f"robots on other machines can reach --listen {endpoint}: give --users FILE or --tls-ca FILE "
                    "so the fleet admits only robots it knows (docs/security.md, Fleet)"
                )
        files = (args.users, args.tls_certificate, args.tls_private_key, args.tls_ca)
        return cls(endpoint, robots, *(path or "" for path in files))

    def zenoh_settings(self) -> dict:
        """The fleet's zenoh settings (key -> value) on top of a router listening on `endpoint`."""
        settings = {"transport/link/rx/max_message_size": MAX_ZENOH_MESSAGE_BYTES}
        if self.users_file:
            settings["transport/auth/usrpwd/dictionary_file"] = self.users_file
        if self.tls_certificate:
            settings["transport/link/tls/listen_certificate"] = self.tls_certificate
            settings["transport/link/tls/listen_private_key"] = self.tls_private_key
        if self.tls_ca:
            settings["transport/link/tls/root_ca_certificate"] = self.tls_ca
            settings["transport/link/tls/enable_mtls"] = True
            settings["transport/link/tls/close_link_on_expiration"] = True
        settings["access_control"] = access_control(self.robots, bool(self.users_file), bool(self.tls_ca))
        return settings


def access_control(robots: tuple[str, ...], by_user: bool, by_certificate: bool) -> dict:
    """Zenoh's ACL: robot R (user R, certificate common name R, or both) may put and delete under `joshua/R/**`;
    without names, any peer may under `joshua/**`. Everything else is denied."""
    rules, subjects, policies = [], [], []
    for robot in robots or (ANYONE,):
        key = f"{KEY_ROOT}/{robot}/**" if robots else f"{KEY_ROOT}/**"
        rules.append(
            {
                "id": robot,
                "messages": PUBLISHED_MESSAGES,
                "flows": ["ingress"],
                "permission": "allow",
                "key_exprs": [key],
            }
        )
        subject = {"id": robot}
        if robots and by_user:
            subject["usernames"] = [robot]
        if robots and by_certificate:
            subject["cert_common_names"] = [robot]
        subjects.append(subject)
        policies.append({"rules": [robot], "subjects": [robot]})
    return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects, "policies": policies}


def read_users(path: str) -> tuple[str, ...]:
    """The robots of a zenoh user/password dictionary, read as zenoh reads it (`USER:PASSWORD` per line,
    spaces around each trimmed, blank lines skipped); errors name the line, never its password."""
    names = []
    for number, line in _lines("--users", path):
        user, colon, password = line.partition(":")
        if not colon or not user.strip() or not password.strip():
            raise SettingsError(f"{path}:{number}: not ROBOT:PASSWORD")
        names.append(_robot_name(path, number, user.strip(), names))
    if not names:
        raise SettingsError(f"{path}: no ROBOT:PASSWORD line")
    return tuple(names)


def read_robots(path: str) -> tuple[str, ...]:
    """Robot names, one a line; `#` starts a comment."""
    names = []
    for number, line in _lines("--robots", path):
        name = line.partition("#")[0].strip()
        if name:
            names.append(_robot_name(path, number, name, names))
    if not names:
        raise SettingsError(f"{path}: no robot name")
    return tuple(names)


def _robot_name(path: str, number: int, name: str, earlier: list[str]) -> str:
    if not is_robot_name(name):
        raise SettingsError(
            f'{path}:{number}: "{name[:80]}" is not a robot name (lower-case letters, digits, underscores)'
        )
    if name in earlier:
        raise SettingsError(f"{path}:{number}: {name} is listed twice")
    return name


def _lines(flag: str, path: str):
    try:
        with open(path, encoding="utf-8") as file:
            text = file.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise SettingsError(f"cannot read {flag} {path}: {getattr(exc, 'strerror', None) or exc}") from exc
    return [(number, line.strip()) for number, line in enumerate(text.splitlines(), 1) if line.strip()]


def _readable(flag: str, path: str) -> None:
    try:
        with open(path, "rb"):
            pass
    except OSError as exc:
        raise SettingsError(f"cannot read {flag} {path}: {exc.strerror or exc}") from exc
