"""The Discovery Server as a node of a supervisor: started, announced ready once it serves, stopped on a signal.

    python -m joshua_runtime.discovery.supervised --address 10.0.0.2 [--port 11811] [--server-id 0] [--profile XML]

The generated entrypoint of the `discovery_server` process runs this. It starts `fast-discovery-server`
as server.py would, passes its output on, sends READY=1 (sd_notify) when the server prints that it
is running (it has bound its UDP port by then), feeds the watchdog systemd asks for, and hands SIGINT
and SIGTERM to the server; its exit code is the server's (0 when a stop signal ended it). Exit code 2
with one line when the binary is missing or the arguments are bad.

Without --profile the server gets server_profile.xml (a 2 s lease), and after a crash it starts again
only once its clients have dropped the crashed one (restart_pause.py), whichever launcher restarts it.
"""

import os
import select
import selectors
import signal
import subprocess
import sys
import time
from pathlib import Path

from joshua_runtime.discovery import restart_pause, server
from joshua_runtime.notify import Notifier

RUNNING_LINE = "Server is running"  # what fast-discovery-server prints once it serves
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
WAKE_S = restart_pause.HEARTBEAT_S  # how often the watchdog and the heartbeat are looked at
DEFAULT_PROFILE = Path(__file__).with_name("server_profile.xml")
STOP_TIMEOUT_S = 5.0  # the server's own shutdown, after which it is killed
EXIT_USAGE = 2


def main(argv: list[str] | None = None) -> int:
    args = server.arguments("python -m joshua_runtime.discovery.supervised", __doc__.splitlines()[0], argv)
    problem = server.cannot_start(args)
    if problem:
        print(problem, file=sys.stderr)
        return EXIT_USAGE
    profile = args.profile or str(DEFAULT_PROFILE)
    try:
        lease_s = restart_pause.lease_s(profile)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    heartbeat = restart_pause.heartbeat_path(args.address, args.port)
    notifier = Notifier.from_environment()
    stop_requested = []
    read_signal, write_signal = os.pipe()
    os.set_blocking(write_signal, False)
    signal.set_wakeup_fd(write_signal, warn_on_full_buffer=False)
    for number in STOP_SIGNALS:
        signal.signal(number, lambda number, _frame: stop_requested.append(number))
    if not wait_for_crashed_server_to_expire(heartbeat, lease_s, read_signal, stop_requested, notifier):
        return 0
    child = subprocess.Popen(
        server.command(args.address, args.port, args.server_id, profile),
        env=server.environment(dict(os.environ)),  # without the nodes' client profile
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
    )
    selector = selectors.DefaultSelector()
    selector.register(child.stdout, selectors.EVENT_READ)
    selector.register(read_signal, selectors.EVENT_READ)
    pending = b""
    announced = False
    while child.poll() is None:
        if stop_requested:
            child.send_signal(stop_requested.pop(0))
            notifier.stopping()
        for key, _ in selector.select(WAKE_S):
            if key.fileobj == read_signal:
                os.read(read_signal, 4096)
                continue
            data = os.read(child.stdout.fileno(), 65536)
            if not data:
                selector.unregister(child.stdout)
                continue
            sys.stdout.buffer.write(data)
            sys.stdout.flush()
            pending = (pending + data)[-4096:]
            if not announced and RUNNING_LINE.encode() in pending:
                announced = True
                notifier.ready(f"Discovery Server listening on UDP {args.address}:{args.port}")
        notifier.watchdog()
        if announced:  # clients can have matched it only once it serves
            restart_pause.beat(heartbeat)
    try:
        code = child.wait(STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        child.kill()
        code = child.wait()
    rest = child.stdout.read()
    if rest:
        sys.stdout.buffer.write(rest)
        sys.stdout.flush()
    if not stop_requested_or_clean(code):
        return code if code > 0 else 128 - code
    restart_pause.clear(heartbeat)
    return 0


def wait_for_crashed_server_to_expire(heartbeat, lease_s, read_signal, stop_requested, notifier) -> bool:
    """Wait while the clients may still hold a crashed server (restart_pause.py); False when told to stop meanwhile."""
    deadline = time.monotonic() + restart_pause.pause_needed_s(heartbeat, lease_s, time.time())
    if time.monotonic() < deadline:
        line = (
            f"a server on this address crashed less than {restart_pause.LEASES_TO_WAIT} x its {lease_s:g} s lease "
            f"ago: starting in {deadline - time.monotonic():.1f} s, once its clients have dropped it"
        )
        print(line, flush=True)
        notifier.status(line)
    while time.monotonic() < deadline and not stop_requested:
        ready, _, _ = select.select([read_signal], [], [], min(WAKE_S, max(0.0, deadline - time.monotonic())))
        if ready:
            os.read(read_signal, 4096)
        notifier.watchdog()
    return not stop_requested


def stop_requested_or_clean(code: int) -> bool:
    """The server ended as asked: exit code 0, or death by the stop signal it was handed."""
    return code == 0 or -code in STOP_SIGNALS


if __name__ == "__main__":
    sys.exit(main())
