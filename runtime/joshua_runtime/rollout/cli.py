"""`joshua-fleet deploy OUT [...]` and `joshua-fleet rollback ROBOT [--out OUT]`."""

import argparse
import sys
from pathlib import Path

from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.rollout.deploy import POLICIES, deploy, rollback
from joshua_runtime.rollout.inventory import read_inventory
from joshua_runtime.rollout.state import default_state_path, read_state

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2
COMMANDS = ("deploy", "rollback")


def positive_seconds(text: str) -> float:
    value = float(text)
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text} is not a number of seconds above 0")
    return value


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="joshua-fleet", description="Roll a fleet's releases out, or back.")
    commands = parser.add_subparsers(dest="command", required=True)
    deploy_parser = commands.add_parser("deploy", help="roll the releases of `joshuac build FLEET -o OUT` out")
    deploy_parser.add_argument("out", type=Path, metavar="OUT", help="the fleet's output directory")
    deploy_parser.add_argument("--canary", type=int, metavar="N", help="robots first, alone (default: the fleet's)")
    deploy_parser.add_argument(
        "--batch", type=int, metavar="N", help="robots at once after them (default: the fleet's)"
    )
    deploy_parser.add_argument(
        "--limit", metavar="P", help="robots to take: names or shell patterns, comma-separated; !P leaves out"
    )
    deploy_parser.add_argument(
        "--on-failure", choices=POLICIES, help="after the canaries, a failed robot stops the rollout or is skipped"
    )
    deploy_parser.add_argument("--health-timeout", type=positive_seconds, metavar="S", help="seconds to be ready")
    rollback_parser = commands.add_parser("rollback", help="take a robot back to its previous release")
    rollback_parser.add_argument("robot", metavar="ROBOT")
    rollback_parser.add_argument("--out", type=Path, help="the fleet's output directory (default: the last deploy's)")
    for command in (deploy_parser, rollback_parser):
        command.add_argument(
            "--state", type=Path, default=None, metavar="FILE", help="the rollout's state file (default: %(default)s)"
        )
    return parser.parse_args(argv)


def say(line: str) -> None:
    print(f"joshua-fleet: {line}", flush=True)


def main(argv) -> int:
    args = parse_arguments(argv)
    state_path = args.state or default_state_path()
    try:
        if args.command == "deploy":
            inventory = read_inventory(args.out)
            done = deploy(
                inventory, state_path, say, args.limit, args.canary, args.batch, args.on_failure, args.health_timeout
            )
        else:
            out = args.out
            if out is None:
                last = read_state(state_path) or {}
                if not last.get("out"):
                    raise SettingsError(f"no rollout recorded in {state_path}: give --out OUT")
                out = Path(last["out"])
            done = rollback(read_inventory(out), args.robot, state_path, say)
    except SettingsError as exc:
        print(f"joshua-fleet: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except JoshuaError as exc:
        print(f"joshua-fleet: error: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        return 130
    return EXIT_OK if done else EXIT_FAILED
