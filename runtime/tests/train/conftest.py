"""Training tests: the offscreen GL backend before MuJoCo is imported, and one PPO policy trained per session.

The session's PPO run (LEARNING_STEPS on so100_reach, fixed seed) is shared by the learning test
and the serving test, so the CPU pays for it once.
"""

import pytest

from joshua_runtime.sim.gl_backend import configure_gl

configure_gl("egl")

from train_support import EVALUATION_EPISODES, LEARNING_SEED, LEARNING_STEPS  # noqa: E402


@pytest.fixture(scope="session")
def trained_reach(tmp_path_factory):
    """(output directory, metadata) of a short PPO run on so100_reach."""
    from joshua_runtime.train import ppo

    output = tmp_path_factory.mktemp("ppo") / "reach"
    metadata = ppo.train(
        "so100_reach",
        LEARNING_STEPS,
        output,
        seed=LEARNING_SEED,
        checkpoint_every=LEARNING_STEPS,
        eval_episodes=EVALUATION_EPISODES,
        progress=False,
        log=lambda text: None,
    )
    return output, metadata
