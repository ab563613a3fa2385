"""Training speed and learning figures: env steps/s, PPO wall time, success rates against baselines.

    .venv/bin/python bench/train.py [--quick]

1. env steps/s of so100_reach on C MuJoCo, random actions, at batch 1, 64 and 1024 (a batch is
   that many environments stepped in turn in this process, as a DummyVecEnv does), and of
   so100_push at batch 1. MJX rows appear when `mujoco-mjx` is installed (the `mjx` extra).
2. PPO's env steps/s on so100_reach with stable-baselines3's DummyVecEnv (4 environments) and with the
   worlds stepped together (--vec-env batch, 16 and 64), while collecting rollouts and over the whole run,
   as ratios to raw physics on every core (support/ppo_throughput.py); then PPO as `joshua-train rl` runs
   it by default (seed 0): wall time, steps/s, and its evaluation next to the random baseline (success
   rate, mean return, mean final distance).
3. Imitation round trip: scripted demonstrations -> ACT (joshua-train imitation) -> evaluation,
   next to the zeros baseline; skipped with --quick.
4. Seconds per training step of `joshua-train imitation` and of LeRobot's `lerobot-train`, the same
   ACT on the same 320x240 video recording (support/training_steps.py), lerobot-train with torch's
   default threads and with joshua-train's one, run in turn (the best of `rounds` runs each); then
   joshua-train with --image-size 160x120.
--quick: fewer steps everywhere (batch 1024, MJX and imitation skipped, 500 env steps, one PPO update of
1024 steps per run and 2 evaluation episodes, a short recording, 2 training steps of batch 1, one round,
lerobot-train on one thread only, no resized run).
"""

import argparse
import importlib.util
import tempfile
import time
from pathlib import Path

import numpy as np

from joshua_runtime.sim.gl_backend import configure_gl

configure_gl()

from support import ppo_throughput, training_steps  # noqa: E402

from joshua_runtime.train import actors, envs, evaluation, imitation, ppo  # noqa: E402  (after GL is chosen)
from testsupport import tiny_act  # noqa: E402

# The step-time comparison (section 4): recording, training steps, batch, data-loader workers, rounds, and
# whether lerobot-train also runs on torch's default threads (one per core).
STEP_RUN = dict(episodes=4, frames=50, steps=20, batch_size=4, workers=2, rounds=2, default_threads=True)
QUICK_STEP_RUN = dict(episodes=1, frames=10, steps=2, batch_size=1, workers=0, rounds=1, default_threads=False)
# --quick: env steps per batch, and PPO steps of each run (one update: ppo.SAMPLES_PER_UPDATE) and its evaluation
QUICK_ENV_STEPS, QUICK_PPO_STEPS, QUICK_EPISODES = 500, ppo.SAMPLES_PER_UPDATE, 2
RESIZED = "160x120"


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
    steps = QUICK_ENV_STEPS if args.quick else 20_000
    print("== env steps/s (C MuJoCo, random actions)")
    for batch in (1, 64) if args.quick else (1, 64, 1024):
        print(f"mujoco so100_reach batch {batch:>4}: {env_steps_per_s(envs.REACH, batch, steps):10.0f} env steps/s")
    print(f"mujoco so100_push  batch    1: {env_steps_per_s(envs.PUSH, 1, steps // 2):10.0f} env steps/s")
    for row in mjx_rows(args.quick):
        print(row)

    print("== PPO env steps/s against raw physics on every core (so100_reach)")
    ppo_throughput.report(QUICK_PPO_STEPS if args.quick else 30_000)
    ppo_steps = QUICK_PPO_STEPS if args.quick else 30_000
    episodes = QUICK_EPISODES if args.quick else 50
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
        step_times(Path(scratch), QUICK_STEP_RUN if args.quick else STEP_RUN, resized=not args.quick)


def imitation_round_trip(scratch: Path, demonstrations: int = 10, train_steps: int = 200, episodes: int = 20) -> None:
    from joshua_runtime.train import demonstrations as demos

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


def step_times(scratch: Path, settings: dict, resized: bool) -> None:
    width, height = tiny_act.WIDTH, tiny_act.HEIGHT
    dataset = tiny_act.record_dataset(
        scratch / "recording", settings["episodes"], settings["frames"], (width, height), use_videos=True
    )
    run = training_steps.Run(dataset, settings["steps"], settings["batch_size"], settings["workers"])
    print(
        f"== seconds per training step: ACT (joshua-train's sizes), {settings['episodes']} episodes x "
        f"{settings['frames']} frames of {width}x{height} video, batch {run.batch_size}, {run.workers} workers, CPU"
    )
    one_thread = imitation.TORCH_THREADS
    contenders = {
        "joshua-train imitation": (training_steps.joshua_train, None),
        "lerobot-train": (training_steps.lerobot_train, None),
        f"lerobot-train, OMP_NUM_THREADS={one_thread}": (training_steps.lerobot_train, one_thread),
    }
    if not settings["default_threads"]:
        del contenders["lerobot-train"]
    best = {}
    for round_ in range(settings["rounds"]):
        for number, (name, (command, threads)) in enumerate(contenders.items()):
            measured = training_steps.measure(command(run, scratch / f"run-{round_}-{number}"), threads)
            if name not in best or measured.step_s < best[name].step_s:
                best[name] = measured
    for name, measured in best.items():
        print(training_steps.row(name, measured, run.steps))
    ours = best["joshua-train imitation"].step_s
    for name in list(contenders)[1:]:
        print(f"joshua-train imitation / {name}: {ours / best[name].step_s:.2f}x per step")
    if resized:
        smaller = training_steps.Run(dataset, run.steps, run.batch_size, run.workers, image_size=RESIZED)
        measured = training_steps.measure(training_steps.joshua_train(smaller, scratch / "joshua-resized"))
        print(training_steps.row(f"joshua-train imitation --image-size {RESIZED}", measured, run.steps))


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
