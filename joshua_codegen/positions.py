"""Source positions of a loaded description: where each field, repeated element and value was written.

A position is looked up by a path from the root message, e.g.
`("robot_config", "node", 2, "qos_reliability")` for the third node's reliability,
`("robot_config", "node", 0, "device_ids", 3)` for the fourth servo id, and
`("robot_config", "env", "HOME")` for a map entry. Lines and columns are 1-based; `end_column`
is one past the last character.
"""

from __future__ import annotations

from dataclasses import dataclass

Path = tuple[str | int, ...]
ROBOT: Path = ("robot_config",)


def node_path(index: int) -> Path:
    """Path of the index-th node."""
    return ("robot_config", "node", index)


@dataclass(frozen=True)
class Location:
    path: str  # the file (or "--set" for a command-line override)
    line: int
    column: int
    end_line: int | None = None
    end_column: int | None = None


class SourceMap:
    """Locations by message path for one file; copy-on-write for overrides."""

    def __init__(self, path: str, locations: dict[Path, Location] | None = None):
        self.path = path
        self._locations: dict[Path, Location] = dict(locations or {})

    def add(self, key: Path, location: Location) -> None:
        """Record where `key` was written; the first record of a path wins."""
        self._locations.setdefault(key, location)

    def get(self, key: Path) -> Location | None:
        """Where `key` itself was written, or None when it was not."""
        return self._locations.get(key)

    def locate(self, key: Path) -> Location:
        """Where `key` was written, else its closest written ancestor, else the file start."""
        for length in range(len(key), 0, -1):
            found = self._locations.get(key[:length])
            if found is not None:
                return found
        return Location(self.path, 1, 1)

    def replaced(self, key: Path, location: Location) -> SourceMap:
        """A copy where `key` and everything under it now comes from `location` (an override)."""
        size = len(key)
        kept = {k: v for k, v in self._locations.items() if k[:size] != key}
        kept[key] = location
        return SourceMap(self.path, kept)

    def __len__(self) -> int:
        return len(self._locations)
