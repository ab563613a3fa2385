"""The robots and rollout settings of a fleet's generated inventory (OUT/ansible/inventory.yml)."""

from dataclasses import dataclass
from pathlib import Path

import yaml

from joshua_runtime.errors import SettingsError

ANSIBLE_DIR = "ansible"
INVENTORY = "inventory.yml"
DEPLOY_PLAYBOOK = "deploy.yml"
ROLLBACK_PLAYBOOK = "rollback.yml"
SSH_PORT = 22  # Ansible's, when the inventory names none


@dataclass(frozen=True)
class Robot:
    """One computer the rollout reaches: a robot, or one host of a robot on several (`<robot>.<host>`)."""

    name: str  # its name in the inventory
    robot: str  # the robot it is (all of a robot's hosts are rolled out together)
    address: str
    release: str  # 12 hex digits
    port: int = SSH_PORT  # its SSH port


@dataclass(frozen=True)
class Inventory:
    out: Path  # the fleet's output directory
    fleet: str
    robots: tuple[Robot, ...]  # in rollout order
    canary: int
    batch: int
    health_timeout_s: float
    on_failure: str  # "stop" | "continue"

    @property
    def path(self) -> Path:
        return self.out / ANSIBLE_DIR / INVENTORY

    def playbook(self, name: str) -> Path:
        return self.out / ANSIBLE_DIR / name

    def computers(self, robot: str) -> list[Robot]:
        """The inventory entries of one robot (its hosts, or itself)."""
        found = [entry for entry in self.robots if robot in (entry.robot, entry.name)]
        if not found:
            names = ", ".join(dict.fromkeys(entry.robot for entry in self.robots))
            raise SettingsError(f"fleet {self.fleet} has no robot {robot} (robots: {names})")
        return found


class _Loader(yaml.SafeLoader):
    """YAML as Ansible writes it: `!unsafe "text"` is text."""


_Loader.add_constructor("!unsafe", lambda loader, node: loader.construct_scalar(node))


def read_inventory(out: Path) -> Inventory:
    """The inventory of the fleet built into `out`; SettingsError when `out` holds no fleet build."""
    path = Path(out) / ANSIBLE_DIR / INVENTORY
    try:
        document = yaml.load(path.read_text(encoding="utf-8"), Loader=_Loader)  # noqa: S506 (a SafeLoader)
        (fleet, group), *_ = document["all"]["children"].items()
        settings, hosts = group["vars"], group["hosts"]
        robots = tuple(
            Robot(
                name,
                str(v["joshua_robot"]),
                str(v["ansible_host"]),
                str(v["joshua_release"]),
                int(v.get("ansible_port", SSH_PORT)),
            )
            for name, v in hosts.items()
        )
        return Inventory(
            out=Path(out),
            fleet=fleet,
            robots=robots,
            canary=int(settings["joshua_canary"]),
            batch=int(settings["joshua_batch"]),
            health_timeout_s=float(settings["joshua_health_timeout_s"]),
            on_failure=str(settings["joshua_on_failure"]),
        )
    except OSError as exc:
        raise SettingsError(
            f"{out} holds no fleet build ({path}: {exc.strerror or exc}); build one with joshuac build FLEET -o OUT"
        ) from None
    except (yaml.YAMLError, KeyError, TypeError, ValueError, AttributeError) as exc:
        raise SettingsError(f"{path} is not an inventory joshuac wrote ({type(exc).__name__}: {exc})") from None
