"""`joshua-registry`: manage the local registry of policies (LeRobot, and PPO from joshua-train).

    joshua-registry import PATH --name NAME [--revision REV] [--trust-pickle]   add a saved policy
    joshua-registry list [NAME]                                 show entries (latest marked with *) and lineage
    joshua-registry resolve registry:NAME[@REV]                 print the directory of an entry
    joshua-registry remove NAME@REV                             delete one revision
    joshua-registry pull REPO_ID [--name NAME] [--hub-revision REV]   download from the Hub, then import

The registry lives in $JOSHUA_MODEL_REGISTRY (default ~/.cache/joshua/models). A policy holding a
pickle (or a symbolic link) is refused, named; `--trust-pickle` converts the stable-baselines3
`policy.zip` of an earlier `joshua-train rl` of your own into weights and JSON (it unpickles that file).
Exit codes: 0 success, 1 failure (missing entry, conflict, unreadable policy), 2 usage error.
"""

import argparse
import sys

from joshua_runtime.ai import registry
from joshua_runtime.errors import JoshuaError


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="joshua-registry", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    add = sub.add_parser("import", help="add a policy saved by LeRobot or by joshua-train rl")
    add.add_argument("path", help="policy directory (or a training output / checkpoint directory)")
    add.add_argument("--name", required=True, help="registry name")
    add.add_argument("--revision", help="revision label (default: digest of the files)")
    add.add_argument(
        "--trust-pickle",
        action="store_true",
        help="convert a stable-baselines3 policy.zip of your own to weights and JSON (this unpickles it: "
        "it runs whatever the file holds)",
    )
    show = sub.add_parser("list", help="list entries")
    show.add_argument("name", nargs="?", help="only this name")
    find = sub.add_parser("resolve", help="print the directory of registry:NAME[@REV]")
    find.add_argument("reference")
    drop = sub.add_parser("remove", help="delete NAME@REV")
    drop.add_argument("reference")
    pull = sub.add_parser("pull", help="download a policy from the Hugging Face Hub and import it")
    pull.add_argument("repo_id")
    pull.add_argument("--name", help="registry name (default: last part of REPO_ID)")
    pull.add_argument("--hub-revision", help="branch, tag or commit on the Hub")
    return parser


def _list(name: str | None) -> None:
    found = registry.entries(name)
    if not found:
        print(f"no models in {registry.root()}" if name is None else f"no revisions of {name} in {registry.root()}")
        return
    latest = {}
    for entry in found:
        latest[entry.name] = entry.revision
    print(f"{'NAME':<24} {'REVISION':<16} {'TYPE':<10} {'IMPORTED':<20} SOURCE")
    for entry in found:
        mark = "*" if latest[entry.name] == entry.revision else " "
        print(
            f"{entry.name:<24} {entry.revision + mark:<16} {entry.policy_type:<10} {entry.imported_at:<20} {entry.source}"
        )
        print(f"{'':<24}   trained on {entry.lineage_text()}")


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "import":
            entry = registry.import_policy(args.path, args.name, args.revision, trust_pickle=args.trust_pickle)
            print(f"{entry.name}@{entry.revision} ({entry.policy_type}) -> {entry.path}")
        elif args.command == "list":
            _list(args.name)
        elif args.command == "resolve":
            reference = (
                args.reference if registry.is_reference(args.reference) else registry.REF_PREFIX + args.reference
            )
            print(registry.resolve(reference).path)
        elif args.command == "remove":
            entry = registry.remove(args.reference)
            print(f"removed {entry.name}@{entry.revision}")
        elif args.command == "pull":
            entry = registry.pull(args.repo_id, args.name, args.hub_revision)
            print(f"{entry.name}@{entry.revision} ({entry.policy_type}) -> {entry.path}")
    except JoshuaError as exc:
        print(f"joshua-registry: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
