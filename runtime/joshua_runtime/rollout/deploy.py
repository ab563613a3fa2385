"""The rollout: canaries, then batches, each robot copied, verified, switched and gated by the deploy playbook.

A canary that fails stops the rollout. After the canaries, a failing robot stops it too (policy `stop`), or is
left on its previous release while the next batches go on (`continue`). Every robot ends with one line: its
ready line and time, the step that failed and why (and the release it went back to), or why it was not started.
"""

import time
from pathlib import Path

from joshua_runtime.rollout.batches import batches, selected
from joshua_runtime.rollout.inventory import DEPLOY_PLAYBOOK, ROLLBACK_PLAYBOOK, Inventory
from joshua_runtime.rollout.playbook import Outcome, run_playbook
from joshua_runtime.rollout.state import RolloutState, read_state, state_dir

POLICIES = ("stop", "continue")


def log_path(fleet: str) -> Path:
    return state_dir() / f"{fleet}-{time.strftime('%Y%m%dT%H%M%S')}.log"


def deploy(
    inventory: Inventory,
    state_path: Path,
    say,
    limit: str | None = None,
    canary: int | None = None,
    batch: int | None = None,
    on_failure: str | None = None,
    health_timeout_s: float | None = None,
) -> bool:
    """Roll the fleet's releases out; `say(line)` reports progress; True when every robot taken got its release."""
    robots = selected(inventory.robots, limit)
    parts = batches(robots, inventory.canary if canary is None else canary, batch or inventory.batch)
    policy = on_failure or inventory.on_failure
    extra = {} if health_timeout_s is None else {"joshua_health_timeout_s": health_timeout_s}
    state = RolloutState.begin(state_path, inventory.fleet, inventory.out, robots)
    log = log_path(inventory.fleet)
    log.parent.mkdir(parents=True, exist_ok=True)
    started = time.time()
    stopped_by = ""
    ok = True
    with open(log, "a", encoding="utf-8") as log_file:
        for label, part in parts:
            if stopped_by:
                for robot in part:
                    state.update(robot.name, state="not_started", message=stopped_by)
                    say(f"{robot.name}: not started: {stopped_by}")
                continue
            say(f"{label}: {', '.join(f'{r.name} (release {r.release})' for r in part)}")
            for robot in part:
                state.update(robot.name, state="deploying")
            batch_started = time.time()
            outcomes = run_playbook(inventory, DEPLOY_PLAYBOOK, [r.name for r in part], log_file, extra)
            failed = []
            for robot in part:
                outcome = outcomes[robot.name]
                seconds = (outcome.finished or time.time()) - batch_started
                record(state, robot.name, outcome, seconds)
                say(outcome.line(robot.release, seconds))
                if not outcome.ok:
                    failed.append(robot.name)
            if failed:
                ok = False
                if label == "canary" or policy == "stop":
                    stopped_by = f"the rollout stopped: {label} {', '.join(failed)} failed"
    state.finish(ok)
    taken = len(robots)
    updated = sum(1 for entry in state.document["robots"] if entry["state"] == "updated")
    say(
        f"fleet {inventory.fleet}: {updated} of {taken} robots on their new release in {time.time() - started:.1f} s "
        f"(ansible's output: {log})"
    )
    return ok


def record(state: RolloutState, name: str, outcome: Outcome, seconds: float) -> None:
    state.update(
        name,
        state="updated" if outcome.ok else "failed",
        step=outcome.step,
        message=outcome.message,
        rolled_back_to=outcome.rolled_back_to,
        seconds=round(seconds, 1),
    )


def rollback(inventory: Inventory, robot: str, state_path: Path, say) -> bool:
    """Take one robot (all its computers) back to its previous release; True when it is ready on it."""
    names = [entry.name for entry in inventory.computers(robot)]
    log = log_path(inventory.fleet)
    log.parent.mkdir(parents=True, exist_ok=True)
    started = time.time()
    with open(log, "a", encoding="utf-8") as log_file:
        outcomes = run_playbook(inventory, ROLLBACK_PLAYBOOK, names, log_file)
    seconds = time.time() - started
    document = read_state(state_path)
    state = RolloutState(state_path, document) if document and document.get("fleet") == inventory.fleet else None
    for name in names:
        outcome = outcomes[name]
        say(f"{name}: {outcome.message} ({seconds:.1f} s)" if outcome.ok else outcome.line("", seconds))
        if state is not None and any(entry.get("name") == name for entry in document.get("robots", [])):
            state.update(
                name, state="rolled_back" if outcome.ok else "failed", step=outcome.step, message=outcome.message
            )
    return all(outcome.ok for outcome in outcomes.values())
