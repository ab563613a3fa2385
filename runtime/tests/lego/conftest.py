"""Fixtures of the LEGO base tests: a Pybricks hub driver connected to an emulated hub on a Bumble link."""

import pytest

from joshua_runtime.drivers.pybricks import PybricksHub
from joshua_runtime.drivers.pybricks_bumble import BumbleTransport
from joshua_runtime.drivers.pybricks_program import program_blob
from joshua_runtime.emulators.pybricks import HubFaults
from joshua_runtime.emulators.pybricks_link import in_process

HUB_NAME = "Pybricks Hub"


@pytest.fixture(scope="session")
def blob() -> bytes:
    return program_blob()


@pytest.fixture
def linked_hub(blob):
    """Factory: linked_hub(faults=None, open=True) -> (driver, emulated hub) on one in-process link.

    What the emulated hub reports about the faults it injects is kept in its `reports` list.
    """
    made = []

    def make(faults: HubFaults | None = None, open: bool = True):
        driver = PybricksHub(HUB_NAME, None, blob)
        reports = []
        emulated, central = driver.run_on_loop(in_process(HUB_NAME, faults, reports.append), 5.0)
        emulated.reports = reports
        driver.transport = BumbleTransport(device=central)
        made.append((driver, emulated))
        if open:
            driver.open()
        return driver, emulated

    yield make
    for driver, _emulated in made:
        driver.close()
