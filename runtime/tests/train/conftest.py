"""Training tests: the offscreen GL backend before MuJoCo is imported, JAX's compilation cache, and one PPO
policy trained per session.

The session's PPO run (LEARNING_STEPS on so100_reach, fixed seed) is shared by the learning test
and the serving test, so the CPU pays for it once.
"""

import os

import pytest

from joshua_runtime.sim.gl_backend import configure_gl

configure_gl("egl")

from train_support import EVALUATION_EPISODES, LEARNING_ENVS, LEARNING_SEED, LEARNING_STEPS  # noqa: E402


def pytest_configure(config):
    """JAX keeps what it compiles in pytest's cache directory, so that a later run of the MJX test loads its
    step function (about a minute of compilation on a CPU) instead of compiling it again; the first run on
    a checkout compiles as before."""
    cache = getattr(config, "cache", None)
    if cache is not None:
        os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", str(cache.mkdir("jax-compilation")))


@pytest.fixture(scope="session")
def trained_reach(tmp_path_factory):
    """(output directory, metadata) of a short PPO run on so100_reach, its worlds stepped together (--vec-env batch)."""
    from joshua_runtime.train import ppo

    output = tmp_path_factory.mktemp("ppo") / "reach"
    metadata = ppo.train(
        "so100_reach",
        LEARNING_STEPS,
        output,
        seed=LEARNING_SEED,
        checkpoint_every=LEARNING_STEPS,
        eval_episodes=EVALUATION_EPISODES,
        vec_env="batch",
        settings=ppo.PpoSettings.for_envs(LEARNING_ENVS),
        progress=False,
        log=lambda text: None,
    )
    return output, metadata
