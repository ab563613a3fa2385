"""Helpers of the servo tests: the SO-100 bus layout and polling.

Node settings come from the compiler (testsupport/compiled_settings.py), node processes from
testsupport/node_process.py and the in-process rclpy client from testsupport/ros_client.py.
"""

import time

from joshua_core import so100

SO100_JOINTS = list(so100.SO100_JOINTS)
SO100_IDS = [1, 2, 3, 4, 5, 6]
WAIT_POLL_S = 0.02


def wait_for(predicate, timeout_s: float) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(WAIT_POLL_S)
    return bool(predicate())
