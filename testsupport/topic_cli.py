"""Run `joshua-topic` as its users do: a process of its own, in the test's ROS environment."""

import subprocess
import sys

CLI_TIMEOUT_S = 60.0


def topic_cli(env, *args, timeout=CLI_TIMEOUT_S) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "joshua_runtime.tools.topic_cli", *map(str, args)],
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
