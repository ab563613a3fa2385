"""`joshua-train`: train behaviours in simulation or from recorded demonstrations, and evaluate them.

    joshua-train rl --env ENV --steps N --output DIR [--seed S]        PPO (resumes a run in DIR)
                    [--backend mujoco|mjx] [--vec-env dummy|subproc|batch] [--n-envs K]
    joshua-train imitation --dataset DIR --policy act|diffusion|smolvla --steps N --output DIR
                    [--device auto|cpu|cuda|mps] [--image-size WxH] [--workers W] [--processes N]
    joshua-train evaluate DIR --env ENV --episodes K [--json]          roll a saved policy out
    joshua-train evaluate DIR --dataset DS --episodes IDS [--plot PNG] [--json]
                                                                       actions against held-out episodes
    joshua-train evaluate --replay --dataset DS --episodes IDS [--json]
                                                                       recorded commands on the simulated arm
    joshua-train evaluate --random --env ENV --episodes K [--json]     the random baseline
    joshua-train evaluate --zeros --env so100_reach --episodes K       goal angles 0 (the imitation baseline)
    joshua-train demonstrate --output DIR --episodes K                 scripted so100_reach demonstrations

Environments: so100_reach, so100_push. Exit codes: 0 success, 1 failure, 2 bad arguments or settings, 130 interrupted.
"""

import argparse
import contextlib
import json
import sys
from pathlib import Path

from joshua_runtime.ai import cpu_threads
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.process_end import end_process
from joshua_runtime.sim.gl_backend import configure_gl
from joshua_runtime.train.devices import DEVICES
from joshua_runtime.train.imitation import DEFAULT_WORKERS, POLICIES

DEFAULT_CHECKPOINT_EVERY = 10_000
DEFAULT_EVAL_EPISODES = 20


def _parser() -> argparse.ArgumentParser:
    from joshua_runtime.train.envs import ENVIRONMENTS

    env_help = f"environment ({', '.join(ENVIRONMENTS)})"
    parser = argparse.ArgumentParser(prog="joshua-train", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    rl = sub.add_parser("rl", help="train PPO on a simulated task")
    rl.add_argument("--env", required=True, help=env_help)
    rl.add_argument(
        "--steps", type=int, required=True, help="environment steps in total (a resumed run continues to N)"
    )
    rl.add_argument(
        "--output", required=True, help="run directory: checkpoints, policy.safetensors, joshua_policy.json"
    )
    rl.add_argument("--seed", type=int, default=0)
    rl.add_argument("--checkpoint-every", type=int, default=DEFAULT_CHECKPOINT_EVERY, help="steps between checkpoints")
    rl.add_argument("--eval-episodes", type=int, default=DEFAULT_EVAL_EPISODES, help="episodes of the final evaluation")
    rl.add_argument(
        "--vec-env",
        choices=("dummy", "subproc", "batch"),
        default="dummy",
        help="environments in this process (dummy), one process each (subproc), or stepped together on every core "
        "(batch; so100_reach)",
    )
    rl.add_argument(
        "--backend",
        choices=("mujoco", "mjx"),
        default="mujoco",
        help="C MuJoCo, or MuJoCo-XLA worlds (so100_reach; for GPUs; extra `mjx`)",
    )
    rl.add_argument("--n-envs", type=int, default=4, help="environments (MJX: worlds) stepped together")
    rl.add_argument("--no-progress", action="store_true", help="no progress bar")
    imitation = sub.add_parser("imitation", help="train a LeRobot policy on a recorded dataset")
    imitation.add_argument("--dataset", required=True, help="LeRobotDataset directory (written by DATA_SUBSCRIBER)")
    imitation.add_argument("--policy", required=True, choices=POLICIES)
    imitation.add_argument("--steps", type=int, required=True, help="training steps")
    imitation.add_argument("--output", required=True, help="new directory for LeRobot's output")
    imitation.add_argument(
        "--episodes", help="train on these episodes only (e.g. 0-7), to evaluate on the others (default: all)"
    )
    imitation.add_argument("--seed", type=int, default=0)
    imitation.add_argument("--batch-size", type=int, default=8, help="frames per step and process")
    imitation.add_argument("--device", choices=DEVICES, default="auto", help="auto: cuda, else mps, else cpu")
    imitation.add_argument(
        "--image-size",
        type=_image_size,
        help="resize camera frames to WIDTHxHEIGHT (e.g. 160x120); the policy keeps the size and serving resizes to it",
    )
    imitation.add_argument(
        "--workers", type=int, default=DEFAULT_WORKERS, help="data-loader processes decoding frames (0: in this one)"
    )
    imitation.add_argument(
        "--processes", type=int, default=1, help="data-parallel training processes (one per GPU, or CPU processes)"
    )
    imitation.add_argument(
        "--vlm", help="smolvla: the vision-language backbone, a directory or Hub id (default: a small one made here)"
    )
    imitation.add_argument(
        "--eval-episodes",
        type=int,
        default=0,
        help="evaluate on so100_reach afterwards (for demonstrations made by `demonstrate`)",
    )
    evaluate = sub.add_parser("evaluate", help="roll a policy out in simulation, or compare it with held-out episodes")
    evaluate.add_argument("directory", nargs="?", help="policy directory (joshua-train rl output or a LeRobot policy)")
    evaluate.add_argument("--env", help=env_help)
    evaluate.add_argument(
        "--episodes", required=True, help="simulated episodes K, or with --dataset the held-out episode indices (8,9)"
    )
    evaluate.add_argument(
        "--dataset", help="LeRobot dataset whose held-out episodes the policy's actions are compared with"
    )
    evaluate.add_argument(
        "--plot", help="with --dataset: PNG of predicted and recorded actions (default evaluation-<dataset>.png here)"
    )
    evaluate.add_argument("--device", default="cpu", help="with --dataset: torch device of the policy (cpu, cuda)")
    evaluate.add_argument(
        "--replay",
        action="store_true",
        help="with --dataset: drive the simulated SO-100 with the episodes' recorded commands, compare its joints",
    )
    evaluate.add_argument("--random", action="store_true", help="uniform random actions (the baseline)")
    evaluate.add_argument(
        "--zeros",
        action="store_true",
        help="goal angle 0 for every joint, on the demonstrations' goal (the imitation baseline)",
    )
    evaluate.add_argument("--json", action="store_true", help="print the result as JSON")
    demonstrate = sub.add_parser("demonstrate", help="record scripted so100_reach demonstrations as a LeRobot dataset")
    demonstrate.add_argument("--output", required=True, help="dataset directory (appended to when it exists)")
    demonstrate.add_argument("--episodes", type=int, required=True)
    demonstrate.add_argument("--seed", type=int, default=0)
    return parser


def run_evaluation(directory, env_id: str, episodes: int, baseline: str = "") -> dict:
    """Roll out the policy in `directory`, or a baseline ("random" or "zeros")."""
    from joshua_runtime.train import actors, evaluation

    if baseline:
        actor = actors.random_actor() if baseline == "random" else actors.zeros_actor()
    else:
        actor = actors.load_actor(directory, env_id)
    try:
        return evaluation.evaluate(actor.make_act, env_id, episodes, actor.env_kwargs, reset=actor.reset)
    finally:
        actor.close()


def _rl(args) -> None:
    from joshua_runtime.train import ppo
    from joshua_runtime.train.evaluation import summary

    if args.n_envs < 1:
        raise SettingsError(f"--n-envs must be positive, got {args.n_envs}")
    settings = ppo.PpoSettings.for_envs(args.n_envs)
    metadata = ppo.train(
        args.env,
        args.steps,
        Path(args.output),
        args.seed,
        args.checkpoint_every,
        args.eval_episodes,
        args.vec_env,
        settings,
        progress=not args.no_progress,
        backend=args.backend,
    )
    print(f"saved PPO policy for {args.env} after {metadata['steps']} steps in {args.output}")
    if metadata["evaluation"]:
        print(summary(metadata["evaluation"]))


def _image_size(text: str) -> tuple[int, int]:
    from joshua_runtime.ai.images import parse_size

    try:
        return parse_size(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from exc


def _imitation(args, argv: list[str]) -> None:
    from joshua_runtime.ai import saved_policy
    from joshua_runtime.train import dataset_evaluation, imitation, launch
    from joshua_runtime.train.envs import REACH
    from joshua_runtime.train.evaluation import summary

    if args.processes < 1:
        raise SettingsError(f"--processes must be positive, got {args.processes}")
    options = imitation.TrainingOptions(
        seed=args.seed,
        batch_size=args.batch_size,
        device=args.device,
        image_size=args.image_size,
        workers=args.workers,
        vlm=args.vlm,
        episodes=dataset_evaluation.parse_episodes(args.episodes) if args.episodes else None,
    )
    if args.processes > 1 and not launch.launched():
        pretrained = _launch_processes(args, argv, options)
    else:
        pretrained = imitation.train(Path(args.dataset), args.policy, args.steps, Path(args.output), options)
        if not launch.is_main_process():
            return
    metadata = saved_policy.read(pretrained)
    print(f"saved {args.policy} policy in {pretrained}")
    print(imitation.loss_summary(metadata))
    if args.eval_episodes > 0:
        result = run_evaluation(pretrained, REACH, args.eval_episodes)
        saved_policy.update(pretrained, evaluation=result)
        print(summary(result))


def _launch_processes(args, argv: list[str], options) -> Path:
    """Run this command as `--processes` processes (launch.py); the policy the first one saved."""
    import tempfile

    from joshua_runtime.ai import model_files
    from joshua_runtime.train import imitation, launch

    imitation.check_dataset(Path(args.dataset))
    output = imitation.check_output(Path(args.output))
    with tempfile.TemporaryDirectory(prefix="joshua-train-vlm-") as scratch:
        if args.policy == "smolvla" and options.vlm is None:
            from joshua_runtime.train import small_vlm  # one backbone for every process

            argv = [*argv, "--vlm", str(small_vlm.write(Path(scratch) / model_files.SMOLVLA_BACKBONE))]
        code = launch.run(args.processes, argv)
    if code != 0:
        raise JoshuaError(f"the {args.processes} training processes failed (exit code {code})")
    return output / imitation.PRETRAINED_SUBDIRECTORY


def _evaluate(args, parser) -> None:
    from joshua_runtime.train.envs import REACH
    from joshua_runtime.train.evaluation import summary

    if args.replay:
        _replay(args, parser)
        return
    if args.dataset:
        _evaluate_on_dataset(args, parser)
        return
    if args.env is None:
        parser.error("give --env ENV (a simulated task) or --dataset DIR (held-out episodes)")
    if (args.random + args.zeros + bool(args.directory)) != 1:
        parser.error("give one of: a policy DIRECTORY, --random, --zeros")
    if args.zeros and args.env != REACH:
        parser.error(f"--zeros is the baseline of {REACH} demonstrations")
    if not args.episodes.isdigit() or int(args.episodes) < 1:
        parser.error(f"--episodes must be positive, got {args.episodes}")
    baseline = "random" if args.random else "zeros" if args.zeros else ""
    with contextlib.redirect_stdout(sys.stderr):  # what LeRobot prints while loading; stdout is the result's
        result = run_evaluation(args.directory, args.env, int(args.episodes), baseline)
    if args.json:
        print(json.dumps({key: result[key] for key in ("success_rate", "mean_return", "episodes")}))
    else:
        print(summary(result))


def _evaluate_on_dataset(args, parser) -> None:
    from joshua_runtime.train import dataset_evaluation

    if not args.directory or args.random or args.zeros or args.env:
        parser.error("--dataset compares a policy DIRECTORY with held-out episodes (no --env, --random, --zeros)")
    episodes = dataset_evaluation.parse_episodes(args.episodes)
    plot = Path(args.plot) if args.plot else Path(f"evaluation-{Path(args.dataset).name}.png")
    with contextlib.redirect_stdout(sys.stderr):  # what LeRobot prints while loading; stdout is the result's
        result = dataset_evaluation.evaluate(Path(args.directory), Path(args.dataset), episodes, plot, args.device)
    print(json.dumps(result) if args.json else dataset_evaluation.summary(result))


def _replay(args, parser) -> None:
    from joshua_runtime.train import dataset_evaluation, replay

    if not args.dataset or args.directory or args.random or args.zeros or args.env or args.plot:
        parser.error("--replay drives the simulation with a --dataset's commands (no DIRECTORY, --env, --plot)")
    result = replay.replay(Path(args.dataset), dataset_evaluation.parse_episodes(args.episodes))
    print(json.dumps(result) if args.json else replay.summary(result))


def main(argv: list[str] | None = None) -> int:
    """Run the command line `argv` and return its exit code; without `argv` (the `joshua-train` script),
    run sys.argv and end the process (process_end.py): torch's and LeRobot's teardown at interpreter
    exit would add 1.4-2.7 s to every command on a busy 2-core machine."""
    if argv is not None:
        return _run(list(argv))
    end_process(_run(sys.argv[1:]))


def _run(argv: list[str]) -> int:
    configure_gl()  # before MuJoCo is imported: demonstrations and LeRobot evaluations render a camera
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "rl":
            _rl(args)
        elif args.command == "imitation":
            _imitation(args, argv)
        elif args.command == "evaluate":
            cpu_threads.prepare()  # before torch loads: spinning workers slow an evaluation on a busy CPU 6-8x
            _evaluate(args, parser)
        elif args.command == "demonstrate":
            from joshua_runtime.train import demonstrations

            demonstrations.record(Path(args.output), args.episodes, args.seed)
            print(f"recorded {args.episodes} demonstrations in {args.output}")
    except JoshuaError as exc:
        print(f"joshua-train: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("joshua-train: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))  # returns, so that `python -m cProfile -m joshua_runtime.train.cli` can report
