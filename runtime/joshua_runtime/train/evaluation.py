"""Rollouts of a policy in a training environment: success rate and mean return over K episodes."""

from collections.abc import Callable

import numpy as np

from joshua_runtime.train import envs

# Seeds of evaluation episodes start here, away from the seeds training uses.
EVALUATION_SEED = 10_000


def evaluate(
    make_act: Callable,
    env_id: str,
    episodes: int,
    env_kwargs: dict | None = None,
    seed: int = EVALUATION_SEED,
    reset: Callable[[], None] | None = None,
) -> dict:
    """Run `episodes` episodes with `make_act(unwrapped env)`, a function `observation -> action`
    (or None: uniform random actions).

    `reset` (when given) is called before each episode, for policies that keep a history.
    Returns {"success_rate", "mean_return", "episodes", "env", "mean_final_distance"}.
    """
    if episodes < 1:
        raise ValueError("episodes must be at least 1")
    env = envs.make(env_id, **(env_kwargs or {}))
    env.action_space.seed(seed)
    act = make_act(env.unwrapped)
    returns, successes, distances = [], [], []
    try:
        for episode in range(episodes):
            observation, info = env.reset(seed=seed + episode)
            if reset is not None:
                reset()
            total, done = 0.0, False
            while not done:
                action = env.action_space.sample() if act is None else act(observation)
                observation, reward, terminated, truncated, info = env.step(action)
                total += float(reward)
                done = terminated or truncated
            returns.append(total)
            successes.append(bool(info.get("is_success", False)))
            distances.append(float(info.get("distance", np.nan)))
    finally:
        env.close()
    return {
        "success_rate": round(float(np.mean(successes)), 4),
        "mean_return": round(float(np.mean(returns)), 4),
        "episodes": episodes,
        "env": env_id,
        "mean_final_distance": round(float(np.mean(distances)), 4),
    }


def summary(result: dict) -> str:
    """One readable line of an evaluation result."""
    return (
        f"{result['env']}: success rate {result['success_rate']:.2f} over {result['episodes']} episodes, "
        f"mean return {result['mean_return']:.2f}, mean final distance {result['mean_final_distance']:.3f} m"
    )
