"""The event listener supervisord.conf runs to stop the robot when a critical node fails."""

import os
import signal
import sys

from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.policy import EXIT_OK
from joshua_codegen.supervisor.robot import ROBOT


def supervisord_listener():
    """The event listener supervisord.conf runs: supervisord cannot stop a group when one of its
    programs fails, so this stops supervisord itself (SIGTERM: it then stops every node) when a
    critical node fails for good: FATAL (restarts exhausted), or a failed exit of a node that is never
    restarted. Speaks supervisord's listener protocol on stdin/stdout; logs on stderr."""
    group = ROBOT["supervisord_group"]
    critical = {spec["name"]: spec for spec in ROBOT["processes"] if spec["critical"]}
    stdin, stdout = sys.stdin.buffer, sys.stdout.buffer
    while True:
        stdout.write(b"READY\n")
        stdout.flush()
        line = stdin.readline()
        if not line:
            return EXIT_OK
        header = dict(token.split(":", 1) for token in line.decode().split())
        payload = stdin.read(int(header["len"])).decode(errors="replace")
        fields = dict(token.split(":", 1) for token in payload.split("\n", 1)[0].split() if ":" in token)
        spec = critical.get(fields.get("processname")) if fields.get("groupname") == group else None
        never_restarted = spec is not None and (spec["restart"] == "RESTART_NEVER" or spec["max_restarts"] == 0)
        event = header.get("eventname")
        if spec is not None and (
            event == "PROCESS_STATE_FATAL"
            or (event == "PROCESS_STATE_EXITED" and fields.get("expected") == "0" and never_restarted)
        ):
            log(
                spec["name"],
                f"{event[len('PROCESS_STATE_') :].lower()}: critical node failed for good; stopping the robot",
            )
            os.kill(os.getppid(), signal.SIGTERM)
        stdout.write(b"RESULT 2\nOK")
        stdout.flush()
