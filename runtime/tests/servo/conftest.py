"""Fixtures of the servo tests: emulated STS3215 buses on ptys (start_node and ros_client: root conftest)."""

import pytest
from servo_helpers import SO100_IDS

from joshua_runtime.emulators.sts3215 import Sts3215Emulator


@pytest.fixture
def emulators(tmp_path):
    """Factory: emulators(name, ids=..., **options) -> a started Sts3215Emulator at tmp_path/name."""
    started = []

    def make(name: str = "ttyBUS", ids=SO100_IDS, **options) -> Sts3215Emulator:
        emulator = Sts3215Emulator(tmp_path / name, ids, **options).start()
        started.append(emulator)
        return emulator

    yield make
    for emulator in started:
        emulator.stop()
