"""Training speed and learning figures: env steps/s, PPO wall time, success rates against baselines.

    .venv/bin/python bench/train.py [--quick]

1. env steps/s of so100_reach on C MuJoCo, random actions, at batch 1, 64 and 1024 (a batch is
   that many environments stepped in turn in this process, as a DummyVecEnv does), and of
   so100_push at batch 1. MJX rows appear when `mujoco-mjx` is installed (the `mjx` extra).
2. PPO on so100_reach (joshua-train rl's settings, seed 0): wall time, steps/s, and its evaluation
   next to the random baseline (success rate, mean return, mean final distance).
3. Imitation round trip: scripted demonstrations -> ACT (joshua-train imitation) -> evaluation,
   next to the zeros baseline; skipped with --quick.
--quick: fewer steps everywhere (batch 1024, MJX and imitation skipped, 5k PPO steps).
"""

import argparse
import importlib.util
import tempfile
import time
from pathlib import Path

import numpy as np

from joshua_runtime.sim.gl_backend import configure_gl

configure_gl()

from joshua_runtime.train import actors, envs, evaluation, ppo  # noqa: E402  (after the GL backend is chosen)


def env_steps_per_s(env_id: str, batch: int, steps: int) -> float:
    worlds = [envs.make(env_id) for _ in range(batch)]
    for seed, env in enumerate(worlds):
        env.reset(seed=seed)
        env.action_space.seed(seed)
    rounds = max(steps // batch, 1)
    start = time.perf_counter()
    for _ in range(rounds):
        for env in worlds:
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                env.reset()
    return rounds * batch / (time.perf_counter() - start)


def mjx_rows(quick: bool) -> list[str]:
    if quick:
        return ["mjx: skipped by --quick (each batch size compiles for about a minute on a CPU)"]
    if importlib.util.find_spec("mujoco.mjx") is None or importlib.util.find_spec("jax") is None:
        return ["mjx: not installed (the `mjx` extra)"]
    from joshua_runtime.train import mjx_reach

    rows = []
    for batch in (1, 64, 1024):
        compile_s, rate = mjx_reach.benchmark(batch)
        rows.append(f"mjx so100_reach batch {batch:>4}: {rate:10.0f} env steps/s (compile {compile_s:.1f} s)")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    steps = 2_000 if args.quick else 20_000
    print("== env steps/s (C MuJoCo, random actions)")
    for batch in (1, 64) if args.quick else (1, 64, 1024):
        print(f"mujoco so100_reach batch {batch:>4}: {env_steps_per_s(envs.REACH, batch, steps):10.0f} env steps/s")
    print(f"mujoco so100_push  batch    1: {env_steps_per_s(envs.PUSH, 1, steps // 2):10.0f} env steps/s")
    for row in mjx_rows(args.quick):
        print(row)

    ppo_steps = 5_000 if args.quick else 30_000
    episodes = 10 if args.quick else 50
    print(f"== PPO on so100_reach, {ppo_steps} steps, seed 0")
    with tempfile.TemporaryDirectory() as scratch:
        start = time.perf_counter()
        metadata = ppo.train(
            envs.REACH,
            ppo_steps,
            Path(scratch) / "ppo",
            seed=0,
            checkpoint_every=ppo_steps,
            eval_episodes=episodes,
            progress=False,
            log=lambda text: None,
        )
        wall = time.perf_counter() - start
        print(f"wall time {wall:.1f} s ({metadata['steps'] / wall:.0f} steps/s incl. {episodes} evaluation episodes)")
        print("ppo:    " + evaluation.summary(metadata["evaluation"]))
        print("random: " + evaluation.summary(evaluation.evaluate(lambda env: None, envs.REACH, episodes)))
        if not args.quick:
            imitation_round_trip(Path(scratch))


def imitation_round_trip(scratch: Path, demonstrations: int = 10, train_steps: int = 200, episodes: int = 20) -> None:
    from joshua_runtime.train import demonstrations as demos
    from joshua_runtime.train import imitation

    print(f"== imitation: {demonstrations} scripted demonstrations -> ACT, {train_steps} steps")
    start = time.perf_counter()
    demos.record(scratch / "demos", demonstrations, echo=lambda text: None)
    recorded = time.perf_counter()
    pretrained = imitation.train(scratch / "demos", "act", train_steps, scratch / "act")
    trained = time.perf_counter()
    actor = actors.load_actor(pretrained, envs.REACH)
    result = evaluation.evaluate(actor.make_act, envs.REACH, episodes, actor.env_kwargs, reset=actor.reset)
    actor.close()
    zeros = actors.zeros_actor()
    baseline = evaluation.evaluate(zeros.make_act, envs.REACH, episodes, zeros.env_kwargs)
    print(f"recording {recorded - start:.1f} s, training {trained - recorded:.1f} s")
    print("act:    " + evaluation.summary(result))
    print("zeros:  " + evaluation.summary(baseline))


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
