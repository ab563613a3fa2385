"""Latest-sample-hold of several ROS topics, with the age of each sample for staleness checks.

Ages are measured from the moment a message was received (monotonic clock of this process), not
from its header stamp, so a publisher with a wrong clock cannot make old data look fresh.
"""

import time
from dataclasses import dataclass


@dataclass
class Sample:
    message: object
    received_s: float


class LatestSamples:
    """The last message of each topic name, replaced as new ones arrive."""

    def __init__(self, topic_names: list[str], clock=time.monotonic):
        self.topic_names = list(topic_names)
        self._clock = clock
        self._samples: dict[str, Sample] = {}

    def update(self, topic_name: str, message) -> None:
        self._samples[topic_name] = Sample(message, self._clock())

    def callback(self, topic_name: str):
        """A subscription callback that stores messages of `topic_name`."""
        return lambda message: self.update(topic_name, message)

    def message(self, topic_name: str):
        return self._samples[topic_name].message

    def problems(self, stale_after_s: float) -> list[str]:
        """One phrase per topic that has no sample yet or whose sample is older than `stale_after_s`."""
        now = self._clock()
        found = []
        for name in self.topic_names:
            sample = self._samples.get(name)
            if sample is None:
                found.append(f"{name} has not published yet")
            elif now - sample.received_s > stale_after_s:
                found.append(f"{name} is stale ({now - sample.received_s:.2f} s old)")
        return found
