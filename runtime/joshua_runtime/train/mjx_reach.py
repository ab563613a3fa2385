"""`so100_reach` on MuJoCo-XLA: many worlds stepped at once by jax (`joshua-train rl --backend mjx`), for GPUs.

MJX does not load so100.xml as is (it lacks cylinder-box collisions) and compiles slowly on a CPU,
so it runs a variant of the model (`variant_model`): the arm alone, without the cube, contacts
or constraints (joint ranges are kept by clamping the goals, as the reach task already does).
The task is the one of reach_env.py: same observation, action, reward, goals and episode length;
goals and start angles are drawn on the host, physics runs in jax. On a CPU this is slower than C
MuJoCo and its first step compiles for tens of seconds (see bench/train.py).
"""

from functools import partial

import mujoco
import numpy as np

from joshua_runtime.sim import arm_task as arm
from joshua_runtime.sim.model import model_path


def variant_model() -> mujoco.MjModel:
    """The arm of builtin:so100 at the training timestep, without the cube, contacts or constraints."""
    spec = mujoco.MjSpec.from_file(str(model_path(arm.MODEL)))
    spec.delete(spec.body("cube"))
    for geom in spec.geoms:
        geom.contype = geom.conaffinity = 0
    spec.option.timestep = arm.TRAINING_TIMESTEP_S
    spec.option.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
    return spec.compile()


def _act(mjx_model, addresses, data, action):
    """One action of one world: goals from the present angles, then STEPS_PER_ACTION physics steps."""
    import jax
    import jax.numpy as jnp
    from mujoco import mjx

    positions = data.qpos[addresses.qpos]
    goals = jnp.clip(positions + jnp.clip(action, -1.0, 1.0) * arm.MAX_DELTA_RAD, addresses.low, addresses.high)
    data = data.replace(ctrl=data.ctrl.at[addresses.actuators].set(goals))
    return jax.lax.fori_loop(0, arm.STEPS_PER_ACTION, lambda _, d: mjx.step(mjx_model, d), data)


class MjxWorlds:
    """A batch of variant-model worlds on the default jax device, stepped by one compiled function."""

    def __init__(self, count: int):
        import jax
        from mujoco import mjx

        self.count = count
        self.model = variant_model()
        self.addresses = arm.arm_addresses(self.model)
        self.mjx_model = mjx.put_model(self.model)
        self._blank = mjx.make_data(self.mjx_model)
        self._step = jax.jit(jax.vmap(partial(_act, self.mjx_model, self.addresses)))
        self._forward = jax.jit(jax.vmap(partial(mjx.forward, self.mjx_model)))
        self.data = None

    def reset(self, angles: np.ndarray) -> None:
        """Every world at rest at the given arm angles (count x 4), holding them."""
        import jax.numpy as jnp

        qpos = np.zeros((self.count, self.model.nq))
        qpos[:, self.addresses.qpos] = angles
        ctrl = np.zeros((self.count, self.model.nu))
        ctrl[:, self.addresses.actuators] = angles
        batch = jax_tree_stack(self._blank, self.count).replace(qpos=jnp.asarray(qpos), ctrl=jnp.asarray(ctrl))
        self.data = self._forward(batch)

    def step(self, actions: np.ndarray) -> None:
        import jax.numpy as jnp

        self.data = self._step(self.data, jnp.asarray(actions, dtype=jnp.float32))

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(angles, velocities, grasp points) of every world, as numpy arrays."""
        return (
            np.asarray(self.data.qpos[:, self.addresses.qpos]),
            np.asarray(self.data.qvel[:, self.addresses.dof]),
            np.asarray(self.data.site_xpos[:, self.addresses.grasp]),
        )


def jax_tree_stack(data, count: int):
    import jax
    import jax.numpy as jnp

    return jax.tree_util.tree_map(lambda leaf: jnp.broadcast_to(leaf, (count, *leaf.shape)), data)


def benchmark(batch: int, steps: int = 20) -> tuple[float, float]:
    """(seconds to compile and take the first action, env steps/s after) for `batch` worlds."""
    import time

    import jax

    worlds = MjxWorlds(batch)
    worlds.reset(np.zeros((batch, len(arm.ARM_JOINTS))))
    actions = np.zeros((batch, len(arm.ARM_JOINTS)), np.float32)
    start = time.perf_counter()
    worlds.step(actions)
    jax.block_until_ready(worlds.data)
    compiled = time.perf_counter()
    for _ in range(steps):
        worlds.step(actions)
    jax.block_until_ready(worlds.data)
    return compiled - start, steps * batch / (time.perf_counter() - compiled)
