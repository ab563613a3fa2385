"""ROS-free MuJoCo engine: steps physics on a wall-clock schedule in its own thread.

The physics thread advances the simulation so that simulated time follows wall-clock time times
`realtime_factor` (0: as fast as possible). It steps in small batches while holding `lock`, and
every reader (joint states, ray casts, the camera thread's scene update) takes the same lock for a
short copy, so rendering and publishing never stall physics for more than one copy. When the
process cannot keep up (more than MAX_LAG_S behind), the schedule restarts from the present instead
of trying to catch up, and the dropped time is counted in `dropped_s`.
"""

import threading
import time
from dataclasses import dataclass

import mujoco
import numpy as np

from joshua_runtime.errors import SettingsError
from joshua_runtime.sim.model import joint_id, position_actuator

# Most steps taken under one hold of the lock.
MAX_STEPS_PER_BATCH = 10
# Wall-clock lag after which the schedule restarts from the present.
MAX_LAG_S = 0.25
# Longest the physics thread sleeps before it checks for a stop request.
MAX_SLEEP_S = 0.01
# Time allowed for the physics thread to finish on stop().
STOP_JOIN_TIMEOUT_S = 0.2


@dataclass(frozen=True)
class JointGroup:
    """Joints of one simulated node, resolved to MuJoCo addresses once."""

    names: tuple[str, ...]
    qpos: np.ndarray  # qpos address of each joint
    dof: np.ndarray  # qvel / qfrc address of each joint
    actuators: np.ndarray  # position actuator of each joint, or -1
    ctrl_low: np.ndarray
    ctrl_high: np.ndarray


@dataclass(frozen=True)
class JointReading:
    """Present state of a joint group: positions (rad or m), velocities, actuator efforts."""

    positions: np.ndarray
    velocities: np.ndarray
    efforts: np.ndarray
    sim_time: float


class SimulationEngine:
    """One MuJoCo model and data, stepped in real time (or scaled) by a background thread."""

    def __init__(self, model: mujoco.MjModel, realtime_factor: float = 1.0):
        if realtime_factor is None or realtime_factor < 0:
            raise SettingsError(f"simulation realtime_factor must be >= 0, got {realtime_factor}")
        self.model = model
        self.data = mujoco.MjData(model)
        self.realtime_factor = float(realtime_factor)
        self.lock = threading.Lock()
        self.steps = 0
        self.dropped_s = 0.0
        self._wall_started = self._sim_started = None
        self._wall_stopped = self._sim_stopped = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._hold_initial_pose()
        mujoco.mj_forward(model, self.data)

    def _hold_initial_pose(self) -> None:
        """Point every position actuator at its joint's initial position, so the arm holds still."""
        for aid in range(self.model.nu):
            if int(self.model.actuator_trntype[aid]) == int(mujoco.mjtTrn.mjTRN_JOINT):
                jid = self.model.actuator_trnid[aid, 0]
                self.data.ctrl[aid] = self.data.qpos[self.model.jnt_qposadr[jid]]

    # --- joints -------------------------------------------------------------------------------

    def joints(self, names: list[str], actuated: bool = False) -> JointGroup:
        """Resolve joint names; with `actuated`, every joint must have a position actuator."""
        ids = [joint_id(self.model, name) for name in names]
        actuators = [position_actuator(self.model, j) if actuated else self._actuator_or_none(j) for j in ids]
        low = np.array([self.model.actuator_ctrlrange[a, 0] if a >= 0 else -np.inf for a in actuators])
        high = np.array([self.model.actuator_ctrlrange[a, 1] if a >= 0 else np.inf for a in actuators])
        limited = np.array([a >= 0 and self.model.actuator_ctrllimited[a] for a in actuators], dtype=bool)
        return JointGroup(
            names=tuple(names),
            qpos=np.array([self.model.jnt_qposadr[j] for j in ids], dtype=int),
            dof=np.array([self.model.jnt_dofadr[j] for j in ids], dtype=int),
            actuators=np.array(actuators, dtype=int),
            ctrl_low=np.where(limited, low, -np.inf),
            ctrl_high=np.where(limited, high, np.inf),
        )

    def _actuator_or_none(self, jid: int) -> int:
        try:
            return position_actuator(self.model, jid)
        except SettingsError:
            return -1

    def read(self, group: JointGroup) -> JointReading:
        """Copy the present positions, velocities and actuator efforts of a joint group."""
        with self.lock:
            return JointReading(
                positions=self.data.qpos[group.qpos].copy(),
                velocities=self.data.qvel[group.dof].copy(),
                efforts=self.data.qfrc_actuator[group.dof].copy(),
                sim_time=self.data.time,
            )

    def command(self, group: JointGroup, positions) -> None:
        """Set goal positions (clamped to each actuator's control range); NaN entries are left as they are."""
        goals = np.asarray(positions, dtype=float)
        keep = ~np.isnan(goals) & (group.actuators >= 0)
        goals = np.clip(goals, group.ctrl_low, group.ctrl_high)
        with self.lock:
            self.data.ctrl[group.actuators[keep]] = goals[keep]

    # --- stepping -----------------------------------------------------------------------------

    @property
    def sim_time(self) -> float:
        return self.data.time

    def step(self, count: int = 1) -> None:
        """Advance `count` physics steps now, in the calling thread."""
        with self.lock:
            mujoco.mj_step(self.model, self.data, nstep=count)
        self.steps += count

    def start(self) -> None:
        """Start the physics thread."""
        if self._thread is not None:
            return
        self._stop.clear()
        self._wall_started, self._sim_started = time.monotonic(), self.data.time
        self._wall_stopped = None
        self._thread = threading.Thread(target=self._run, name="sim-physics", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop the physics thread (returns within STOP_JOIN_TIMEOUT_S)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(STOP_JOIN_TIMEOUT_S)
            self._thread = None
            self._wall_stopped, self._sim_stopped = time.monotonic(), self.data.time

    @property
    def started(self) -> bool:
        """True once start() has run."""
        return self._wall_started is not None

    def run_stats(self) -> tuple[float, float]:
        """(simulated seconds, wall-clock seconds) since start(), up to stop() once stopped."""
        if self._wall_started is None:
            return 0.0, 0.0
        if self._wall_stopped is None:
            return self.data.time - self._sim_started, time.monotonic() - self._wall_started
        return self._sim_stopped - self._sim_started, self._wall_stopped - self._wall_started

    def _run(self) -> None:
        timestep = self.model.opt.timestep
        wall_start, sim_start = time.monotonic(), self.data.time
        while not self._stop.is_set():
            if self.realtime_factor == 0:
                self.step(MAX_STEPS_PER_BATCH)
                continue
            now = time.monotonic()
            target = sim_start + (now - wall_start) * self.realtime_factor
            behind = target - self.data.time
            if behind > MAX_LAG_S * self.realtime_factor:
                self.dropped_s += behind / self.realtime_factor
                wall_start, sim_start = now, self.data.time
                behind = 0.0
            due = int(behind / timestep)
            if due > 0:
                self.step(min(due, MAX_STEPS_PER_BATCH))
                continue
            next_step_wall = wall_start + (self.data.time + timestep - sim_start) / self.realtime_factor
            self._stop.wait(min(max(next_step_wall - now, 0.0), MAX_SLEEP_S))
