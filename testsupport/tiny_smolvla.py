"""A real SmolVLA, built and trained offline in seconds: LeRobot's own SmolVLA on a small backbone made here.

The backbone (train/small_vlm.py: a few-layer SmolVLM configuration and a byte-level tokenizer) is
written locally, so nothing comes from the Hub; the policy trains a few steps of LeRobot's loop on
demonstrations recorded like tiny_act's (64x48 camera, 6 joints), whose episodes carry two tasks.
"""

from pathlib import Path

from testsupport import tiny_act

WIDTH, HEIGHT = 64, 48
TASKS = ("follow the bar", "stay still")
EPISODES, FRAMES_PER_EPISODE = 2, 20
TRAINING_STEPS, BATCH_SIZE = 3, 2
CHUNK_SIZE = 5


def train_tiny_smolvla(workdir: Path) -> Path:
    """Record the dataset and train the SmolVLA in `workdir`; the saved policy directory."""
    from joshua_runtime.train import imitation

    dataset = tiny_act.record_dataset(
        Path(workdir) / "dataset", EPISODES, FRAMES_PER_EPISODE, size=(WIDTH, HEIGHT), tasks=TASKS
    )
    options = imitation.TrainingOptions(
        batch_size=BATCH_SIZE, device="cpu", workers=0, sizes={"chunk_size": CHUNK_SIZE, "n_action_steps": 1}
    )
    return imitation.train(dataset, "smolvla", TRAINING_STEPS, Path(workdir) / "smolvla", options)
