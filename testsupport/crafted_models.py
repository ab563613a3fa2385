"""Model files that run code when unpickled, for the tests that prove no loader ever unpickles them.

Each payload writes a marker file when unpickled: a test asserts the marker never appears.
"""

import base64
import json
import pickle
import shutil
import zipfile
from pathlib import Path

SERVING_GOAL = [0.22, 0.06, 0.1]


class WritesMarker:
    """Unpickling this writes `marker` (where a malicious model would do anything else)."""

    def __init__(self, marker: Path):
        self.marker = str(marker)

    def __reduce__(self):
        return (exec, (f"import pathlib; pathlib.Path({self.marker!r}).write_text('unpickled')",))


def payload(marker: Path, protocol: int = pickle.DEFAULT_PROTOCOL) -> bytes:
    return pickle.dumps(WritesMarker(marker), protocol=protocol)


def sb3_zip(path: Path, marker: Path) -> Path:
    """A stable-baselines3 save whose pickled `observation_space` writes `marker` when PPO.load reads it."""
    serialized = base64.b64encode(payload(marker)).decode()
    data = {"observation_space": {":type:": "<class 'gymnasium.spaces.box.Box'>", ":serialized:": serialized}}
    path.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("data", json.dumps(data))
        archive.writestr("_stable_baselines3_version", "2.9.2")
    return path


def ppo_metadata(**fields) -> dict:
    """joshua_policy.json of a `joshua-train rl` run of so100_reach."""
    return {
        "kind": "sb3-ppo",
        "env": "so100_reach",
        "steps": 1024,
        "seed": 0,
        "evaluation": None,
        "joint_names": ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex"],
        "observation": "so100_reach",
        "goal": SERVING_GOAL,
        **fields,
    }


def pickled_ppo_run(directory: Path, marker: Path) -> Path:
    """A `joshua-train rl` output as stable-baselines3 saves it, whose policy.zip writes `marker` when loaded."""
    directory.mkdir(parents=True)
    (directory / "joshua_policy.json").write_text(json.dumps(ppo_metadata()))
    sb3_zip(directory / "policy.zip", marker)
    return directory


def planted_registry_entry(root: Path, name: str, revision: str, policy_dir: Path, policy_type: str) -> Path:
    """A registry entry written without `joshua-registry import` (by hand, or by an earlier version)."""
    entry = root / name / revision
    shutil.copytree(policy_dir, entry)
    record = {
        "name": name,
        "revision": revision,
        "policy_type": policy_type,
        "sequence": 1,
        "imported_at": "2025-01-01T00:00:00Z",
        "source": str(policy_dir),
        "digest": "0" * 64,
        "lineage": None,
    }
    (entry / "joshua_model.json").write_text(json.dumps(record))
    return entry


def forbid_unpickling(monkeypatch) -> None:
    """Make every way into pickle that model loaders use raise (pickle, cloudpickle, torch.load)."""
    import pickle as pickle_module

    import cloudpickle
    import torch

    def refuse(*args, **kwargs):
        raise AssertionError("a model loader unpickled")

    class RefusingUnpickler:
        def __init__(self, *args, **kwargs):
            refuse()

    for module, name in [(pickle_module, "load"), (pickle_module, "loads"), (cloudpickle, "loads"), (torch, "load")]:
        monkeypatch.setattr(module, name, refuse)
    monkeypatch.setattr(pickle_module, "Unpickler", RefusingUnpickler)
