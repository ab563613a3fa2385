"""What a LeRobot policy sees of a simulated task: the six SO-100 joint angles and a small camera image.

The same names as a recorded robot (see ai/features.py): joint states on STATE_TOPIC become
`observation.state`, the goals sent on ACTION_TOPIC become `action`, the camera on CAMERA_TOPIC
becomes `observation.images.camera`. Rendering needs an offscreen OpenGL backend, chosen with
sim/gl_backend.py before MuJoCo is imported.
"""

import mujoco
import numpy as np

from joshua_core.so100 import SO100_JOINTS

STATE_TOPIC = "/so100/joint_states"
ACTION_TOPIC = "/so100/command"
CAMERA_TOPIC = "/camera/image_raw"
CAMERA = "front"
IMAGE_HEIGHT, IMAGE_WIDTH = 48, 64


class ArmView:
    """Reads joint angles and renders the camera of one MuJoCo model and data."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData):
        self.model, self.data = model, data
        joints = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) for name in SO100_JOINTS]
        self.qpos = np.array([model.jnt_qposadr[j] for j in joints])
        self.renderer = mujoco.Renderer(model, IMAGE_HEIGHT, IMAGE_WIDTH)

    def state(self) -> np.ndarray:
        """The six joint angles in SO100_JOINTS order (rad)."""
        return self.data.qpos[self.qpos].astype(np.float32)

    def image(self) -> np.ndarray:
        """The camera image, HWC uint8 RGB."""
        self.renderer.update_scene(self.data, camera=CAMERA)
        return self.renderer.render().copy()

    def close(self) -> None:
        self.renderer.close()
