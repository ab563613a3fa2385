"""`joshua-emulate`: serve an emulated device on a pseudo-terminal until SIGINT or SIGTERM.

    joshua-emulate sts3215 --ids 1,2,3,4,5,6 --link /tmp/ttyLEADER
    joshua-emulate lds01 --link /tmp/ttyLIDAR
"""

import argparse
import signal
import sys


def _ids(text: str) -> list[int]:
    try:
        ids = [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated servo ids, got {text!r}")
    if not ids or any(not 0 <= i <= 253 for i in ids):
        raise argparse.ArgumentTypeError("servo ids must be 0-253")
    return ids


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="joshua-emulate", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="device", required=True)
    sts = sub.add_parser("sts3215", help="a Feetech STS3215 servo bus")
    sts.add_argument(
        "--ids", type=_ids, default=[1, 2, 3, 4, 5, 6], help="servo ids, e.g. 1,2,3 (1,1 wires two servos with id 1)"
    )
    sts.add_argument("--link", required=True, help="path of the symlink to the pty")
    sts.add_argument("--baud-rate", type=int, default=1_000_000, help="line speed the servos start at")
    sts.add_argument("--drop-rate", type=float, default=0.0, help="fraction of replies dropped")
    sts.add_argument("--corrupt-rate", type=float, default=0.0, help="fraction of replies with a bad checksum")
    sts.add_argument("--seed", type=int, default=0, help="seed of the fault injection")
    lds = sub.add_parser("lds01", help="an LDS-01 lidar streaming a synthetic room")
    lds.add_argument("--link", required=True, help="path of the symlink to the pty")
    lds.add_argument("--rpm", type=float, default=300.0, help="rotation speed")
    lds.add_argument("--corrupt-rate", type=float, default=0.0, help="fraction of corrupted packets")
    lds.add_argument("--seed", type=int, default=0, help="seed of the fault injection")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    stop = {"flag": False}

    def request_stop(_signum, _frame):
        stop["flag"] = True

    signal.signal(signal.SIGINT, request_stop)
    signal.signal(signal.SIGTERM, request_stop)
    if args.device == "sts3215":
        from joshua_runtime.emulators.sts3215 import serve
    else:
        from joshua_runtime.emulators.lds01 import serve
    try:
        serve(args, should_stop=lambda: stop["flag"])
    except (OSError, ValueError) as exc:
        print(f"joshua-emulate: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
