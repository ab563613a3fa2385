"""What checking a model costs before it is served: the data-only and registry checks against loading its weights.

    .venv/bin/python bench/model_checks.py [--megabytes 200] [--repeat 5]
    .venv/bin/python bench/model_checks.py --quick      # a 20 MB model, 2 repeats

A policy shaped as LeRobot saves one (config.json, processor pipelines, model.safetensors of random
float32 tensors; 200 MB is LeRobot's default ACT) is imported into a private registry. Reported,
as the best of --repeat runs: the checks an INFERENCE node makes before loading a registry entry
(data_only.check: pickles and processor steps; registry.verify: every file's SHA-256 against
joshua_model.json), their peer, reading the weights into tensors as loading a policy does
(safetensors' load_file, each tensor copied as load_state_dict copies it into the model), and the
ratio of the two. Files are in the page cache for both.
"""

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import torch
from safetensors.torch import load_file, save_file

TENSOR_MEGABYTES = 10  # size of each weight tensor
PIPELINE_STEPS = ["rename_observations_processor", "to_batch_processor", "device_processor"]


def make_policy(directory: Path, megabytes: int) -> Path:
    directory.mkdir()
    (directory / "config.json").write_text(json.dumps({"type": "act"}))
    rng = np.random.default_rng(0)
    floats = TENSOR_MEGABYTES * (1 << 20) // 4
    tensors = {
        f"layer{i}.weight": torch.from_numpy(rng.standard_normal(floats, dtype=np.float32))
        for i in range(max(1, megabytes // TENSOR_MEGABYTES))
    }
    save_file(tensors, str(directory / "model.safetensors"))
    for name in ("policy_preprocessor", "policy_postprocessor"):
        steps = [{"registry_name": step, "config": {}} for step in PIPELINE_STEPS]
        (directory / f"{name}.json").write_text(json.dumps({"name": name, "steps": steps}))
    return directory


def best_of(repeat: int, work) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--megabytes", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="a 20 MB model, 2 repeats")
    args = parser.parse_args()
    megabytes, repeat = (20, 2) if args.quick else (args.megabytes, args.repeat)
    with tempfile.TemporaryDirectory(prefix="bench-model-checks-") as scratch:
        os.environ["JOSHUA_MODEL_REGISTRY"] = str(Path(scratch) / "registry")
        from joshua_runtime.ai import data_only, registry

        entry = registry.import_policy(make_policy(Path(scratch) / "policy", megabytes), "bench")
        size = sum((entry.path / name).stat().st_size for name in entry.files) / (1 << 20)

        def checks():
            data_only.check(entry.path)
            registry.verify(registry.resolve("registry:bench"))

        check_s = best_of(repeat, checks)
        weights = str(entry.path / "model.safetensors")
        load_s = best_of(repeat, lambda: [tensor.clone() for tensor in load_file(weights).values()])
    print(f"== checks before serving a {size:.1f} MB registry entry (best of {repeat})")
    print(f"data_only.check + registry.verify: {check_s:.3f} s ({size / check_s:.0f} MB/s)")
    print(f"weights into tensors (peer):       {load_s:.3f} s")
    print(f"ratio checks / load:               {check_s / load_s:.2f}")


if __name__ == "__main__":
    main()
