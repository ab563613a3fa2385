"""What `joshua-train imitation` adds to LeRobot's own training loop: resized frames and a record of the loss.

LeRobot's `lerobot_train.train` builds its dataset with `make_dataset(cfg)` and runs each step with
`update_policy(...)`, both looked up in its module at call time; `instrumented()` wraps the two for one
run and puts them back afterwards:
- `make_dataset`: with an image size, every camera frame is resized by `images.resize` (the function
  INFERENCE nodes resize camera images with) and the dataset's features say the new shape, so the
  policy is built for, and saved with, that input shape;
- `update_policy`: each step's loss is kept (LossRecord), for joshua_policy.json and the summary line,
  with the backend several processes exchange gradients over (gloo, nccl; None for one process).
"""

import sys
from contextlib import contextmanager

import numpy as np

from joshua_runtime.ai.images import resize

# The loss curve kept in joshua_policy.json: the mean loss of this many equal windows of the run.
LOSS_CURVE_POINTS = 10
_VISUAL_DTYPES = ("image", "video")


class ResizeFrames:
    """A LeRobotDataset image transform: CHW float frames resized to width x height, then `then` (if any).

    A plain class (not a closure): data-loader workers receive the dataset pickled."""

    def __init__(self, width: int, height: int, then=None):
        self.width, self.height, self.then = width, height, then

    def __call__(self, frame):
        import torch

        pixels = frame.permute(1, 2, 0).numpy()
        resized = resize(pixels, self.width, self.height)
        if resized.ndim == 2:
            resized = resized[:, :, None]
        tensor = torch.from_numpy(np.ascontiguousarray(resized)).permute(2, 0, 1)
        return self.then(tensor) if self.then is not None else tensor


def resize_dataset(dataset, size: tuple[int, int]):
    """Make `dataset` (a LeRobotDataset) give its camera frames at `size` (width, height); return it."""
    width, height = size
    for feature in dataset.meta.info["features"].values():
        if feature.get("dtype") in _VISUAL_DTYPES:
            by_name = {"height": height, "width": width}
            feature["shape"] = [by_name.get(name, extent) for name, extent in zip(feature["names"], feature["shape"])]
    dataset.image_transforms = ResizeFrames(width, height, dataset.image_transforms)
    return dataset


class LossRecord:
    """The loss of every training step this process ran, and the distributed backend they ran over."""

    def __init__(self):
        self.losses: list[float] = []
        self.backend: str | None = None

    def wrap(self, update_policy):
        def update(train_tracker, *args, **kwargs):
            tracker, output = update_policy(train_tracker, *args, **kwargs)
            self.losses.append(float(tracker.loss.val))
            self.backend = self.backend or _distributed_backend()
            return tracker, output

        return update

    def curve(self, points: int = LOSS_CURVE_POINTS) -> list[dict]:
        """[{"step": last step of the window, "loss": mean loss of the window}] over `points` equal windows."""
        windows = np.array_split(np.arange(len(self.losses)), min(points, len(self.losses)))
        return [
            {"step": int(window[-1]) + 1, "loss": round(float(np.mean([self.losses[i] for i in window])), 6)}
            for window in windows
        ]


def _distributed_backend() -> str | None:
    import torch.distributed

    if torch.distributed.is_available() and torch.distributed.is_initialized():
        return str(torch.distributed.get_backend())
    return None


@contextmanager
def instrumented(image_size: tuple[int, int] | None, record: LossRecord):
    """LeRobot's training module with resized frames (when `image_size` is given) and `record` kept."""
    from lerobot.scripts import lerobot_train

    make_dataset, update_policy = lerobot_train.make_dataset, lerobot_train.update_policy
    if image_size is not None:
        lerobot_train.make_dataset = lambda cfg: resize_dataset(make_dataset(cfg), image_size)
    lerobot_train.update_policy = record.wrap(update_policy)
    arguments = sys.argv
    sys.argv = arguments[:1]  # LeRobot's config validation reads sys.argv for `--policy.path`
    try:
        yield lerobot_train
    finally:
        lerobot_train.make_dataset, lerobot_train.update_policy = make_dataset, update_policy
        sys.argv = arguments
