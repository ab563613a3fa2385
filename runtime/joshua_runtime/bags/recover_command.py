"""`joshua-topic bag-recover IN OUT`: the subcommand around bag_recover (imported only when it runs: mcap is
an optional dependency, and the other subcommands need ROS instead)."""

import pathlib
import sys


def register(subcommands) -> None:
    """Add `bag-recover IN OUT` to joshua-topic's subcommands; it runs without ROS (`offline`)."""
    command = subcommands.add_parser("bag-recover", help="rewrite a bag cut short (killed recorder) as an indexed one")
    command.add_argument("source", metavar="IN", help="an MCAP file or a bag directory")
    command.add_argument("target", metavar="OUT", help="the recovered file or bag directory (must not exist)")
    command.set_defaults(offline=run)


def run(args) -> int:
    """Exit 0 recovered (one line says what), 1 IN unreadable, 2 IN missing or OUT existing."""
    from joshua_runtime.bags.bag_recover import describe, recover
    from joshua_runtime.errors import JoshuaError

    source, target = pathlib.Path(args.source), pathlib.Path(args.target)
    try:
        results = recover(source, target)
    except JoshuaError as exc:
        print(f"joshua-topic: {exc}", file=sys.stderr)
        return exc.exit_code
    except OSError as exc:
        print(f"joshua-topic: cannot recover {source} into {target}: {exc}", file=sys.stderr)
        return 1
    print(describe(results, target))
    return 0
