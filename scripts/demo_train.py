"""`make demo-train`: scripted demonstrations -> a small ACT -> the registry -> that policy driving the simulated arm.

Every step is a command a user could type (each is printed before it runs), all offline:

1. `joshua-train demonstrate`: scripted reaches of the MuJoCo SO-100 recorded as a LeRobot dataset;
2. `joshua-train imitation`: a small ACT trained by LeRobot's own loop (no pretrained backbone, PyAV,
   a progress bar), evaluated in simulation;
3. `joshua-registry import`: the policy enters the model registry as NAME;
4. `joshuac build` of a MODE_SIMULATION description whose INFERENCE node serves `registry:NAME`,
   and its generated supervisor.py run while this script listens to the arm: once the policy has
   driven it for `--seconds` (counted from its first command, however long the nodes took to start
   and load it), the supervisor is stopped with SIGINT and stops the nodes.

The evidence printed at the end: how many commands the policy sent, and how far the grasp point
was from the demonstrated goal when the policy started and when the run stopped.
Exit codes: 0 success, 1 a step failed or the policy sent nothing, 2 bad arguments, 130 interrupted.
"""

import argparse
import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

BIN = Path(sys.executable).parent
POLICY_NAME = "demo_act"
STATE_TOPIC = "/so100/joint_states"
COMMAND_TOPIC = "/so100/command"
CAMERA_TOPIC = "/camera/image_raw"
# How long the robot may take to start and send the policy's first command (loading LeRobot on a busy CPU).
FIRST_COMMAND_TIMEOUT_S = 300.0
# The supervisor's own --duration beyond that, so that it stops even when this script is killed.
DURATION_MARGIN_S = 60.0
WATCH_SLICE_S = 0.1
DESCRIPTION = """# Written by `make demo-train`: the simulated SO-100 driven by the ACT policy it trained.
robot_config {{
  name: "demo_train"
  mode: MODE_SIMULATION
  simulation {{ model: "builtin:so100" camera: "front" }}
  shutdown {{ sigint_grace_s: 3 sigterm_grace_s: 1 }}
  node {{ name: "arm_encoder" type: ENCODER_PUBLISHER topic_name: "{state}" serial_port: "/dev/ttyACM0" rate_hz: 50 }}
  node {{ name: "arm_actuator" type: ACTUATOR_SUBSCRIBER topic_name: "{command}" serial_port: "/dev/ttyACM1" }}
  node {{ name: "camera" type: CAMERA_PUBLISHER topic_name: "{camera}" width: 64 height: 48 rate_hz: 20 }}
  node {{
    name: "policy"
    type: INFERENCE
    topic_name: "{command}"
    model_path: "registry:{policy}"
    input_topics: ["{state}", "{camera}"]
    rate_hz: 20
  }}
}}
"""


class StepFailed(Exception):
    """A command of the walkthrough exited with an error (it printed why)."""


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="make demo-train", description=__doc__.splitlines()[0])
    parser.add_argument("--output", required=True, help="new (or empty) directory for everything the demo writes")
    parser.add_argument("--episodes", type=int, default=10, help="scripted demonstrations")
    parser.add_argument("--steps", type=int, default=200, help="training steps")
    parser.add_argument("--eval-episodes", type=int, default=10, help="simulated evaluation episodes after training")
    parser.add_argument(
        "--seconds", type=float, default=20.0, help="how long the policy drives the arm, from its first command"
    )
    args = parser.parse_args(argv)
    for name in ("episodes", "steps", "seconds"):
        if getattr(args, name) <= 0:
            parser.error(f"--{name} must be positive, got {getattr(args, name)}")
    return args


def run(*command, env) -> None:
    print("$ " + shlex.join(str(part) for part in command), flush=True)
    if subprocess.run([str(part) for part in command], env=env, check=False).returncode != 0:
        raise StepFailed(f"{Path(str(command[0])).name} failed")


def prepare_output(output: Path) -> bool:
    """Create `output` unless it holds anything already (nothing of the user's is ever overwritten)."""
    if output.exists() and (not output.is_dir() or any(output.iterdir())):
        print(f"demo-train: error: {output} exists and is not empty; name a new directory", file=sys.stderr)
        return False
    output.mkdir(parents=True, exist_ok=True)
    return True


def train_and_import(args, output: Path, env: dict) -> None:
    demos, act = output / "demos", output / "act"
    run(BIN / "joshua-train", "demonstrate", "--output", demos, "--episodes", args.episodes, env=env)
    run(
        *(BIN / "joshua-train", "imitation", "--dataset", demos, "--policy", "act", "--steps", args.steps),
        *("--output", act, "--eval-episodes", args.eval_episodes),
        env=env,
    )
    run(BIN / "joshua-registry", "import", act, "--name", POLICY_NAME, env=env)


def run_in_simulation(args, output: Path, env: dict) -> dict:
    """Build the description, run its supervisor until the policy has driven the arm for `args.seconds`;
    what the arm did meanwhile."""
    description = output / "demo_train.pbtxt"
    description.write_text(
        DESCRIPTION.format(state=STATE_TOPIC, command=COMMAND_TOPIC, camera=CAMERA_TOPIC, policy=POLICY_NAME)
    )
    robot = output / "robot"
    run(BIN / "joshuac", "build", description, "-o", robot, env=env)
    from arm_watch import ArmWatch  # beside this script (rclpy, MuJoCo: imported only now)

    with ArmWatch(STATE_TOPIC, COMMAND_TOPIC) as watch:
        backstop_s = FIRST_COMMAND_TIMEOUT_S + args.seconds + DURATION_MARGIN_S
        supervisor = [sys.executable, robot / "supervisor.py", "--duration", backstop_s]
        supervisor += ["--no-control", "--log-dir", output / "logs"]
        print("$ " + shlex.join(str(part) for part in supervisor), flush=True)
        process = subprocess.Popen([str(part) for part in supervisor], env=env)
        try:
            watch_until_driven(watch, process, args.seconds)
            while process.poll() is None:
                watch.spin(WATCH_SLICE_S)
        except KeyboardInterrupt:  # Ctrl-C reached the supervisor too: let its cascade stop the nodes
            process.wait()
            raise
        if process.returncode != 0:
            raise StepFailed(f"supervisor.py exited with {process.returncode} (node logs in {output / 'logs'})")
        return watch.summary()


def watch_until_driven(watch, process: subprocess.Popen, seconds: float) -> None:
    """Listen until the policy has sent commands for `seconds` (or sent none for FIRST_COMMAND_TIMEOUT_S),
    then stop the supervisor with SIGINT, its shutdown cascade."""
    started = time.monotonic()
    while process.poll() is None:
        watch.spin(WATCH_SLICE_S)
        first = watch.first_command_at
        if first is None and time.monotonic() - started > FIRST_COMMAND_TIMEOUT_S:
            print(f"demo-train: no command from the policy within {FIRST_COMMAND_TIMEOUT_S:.0f} s", flush=True)
            break
        if first is not None and time.monotonic() - first >= seconds:
            break
    if process.poll() is None:
        process.send_signal(signal.SIGINT)


def main(argv=None) -> int:
    args = parse_args(argv)
    output = Path(args.output).expanduser().absolute()
    if not prepare_output(output):
        return 2
    env = dict(os.environ)
    env.setdefault("JOSHUA_MODEL_REGISTRY", str(output / "registry"))
    print(f"demo-train: writing into {output}, registry {env['JOSHUA_MODEL_REGISTRY']}", flush=True)
    started = time.monotonic()
    try:
        train_and_import(args, output, env)
        evidence = run_in_simulation(args, output, env)
    except StepFailed as exc:
        print(f"demo-train: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"demo-train: interrupted; what was written so far is in {output}", file=sys.stderr)
        return 130
    if evidence["commands"] == 0 or evidence["start_m"] is None:
        print("demo-train: error: the policy sent no command to the arm", file=sys.stderr)
        return 1
    print(
        f"demo-train: the policy sent {evidence['commands']} commands; the grasp point was "
        f"{evidence['start_m']:.3f} m from the demonstrated goal when it started, "
        f"{evidence['end_m']:.3f} m when the robot stopped ({time.monotonic() - started:.0f} s in all)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
