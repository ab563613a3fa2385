"""How a node process lets torch use the CPU: OpenMP worker threads that sleep, never spin, while they wait.

PyTorch's wheels run CPU kernels on libgomp (OpenMP) worker threads. Unless told otherwise, a worker
that reaches the end of its share of a kernel spins (GOMP_SPINCOUNT 300000 turns) before it sleeps.
On a computer whose cores are all busy (camera, actuator and ROS processes beside the model), the
spinning worker holds a core its partner needs to finish the same kernel, the kernel waits for a
time slice, and a model of hundreds of kernels waits hundreds of times: the tiny ACT of
bench/remote_inference.py took p50 1.2 s per chunk in a node against 0.1 s once its workers slept
while waiting (OMP_WAIT_POLICY=PASSIVE), on the same loaded 2-core machine.

libgomp reads its settings once, when it is loaded with torch, so `prepare()` must run before the
first `import torch` of the process. A policy the environment names is kept: OMP_WAIT_POLICY=ACTIVE
remains a choice for a computer that runs nothing but the model.
"""

import os
import sys

WAIT_POLICY_VARIABLE = "OMP_WAIT_POLICY"
SLEEPING_WORKERS = "PASSIVE"


def prepare(environ=os.environ) -> str:
    """Make libgomp's workers sleep while they wait, unless the environment names a policy.

    Returns "" when done (or left to the user's setting), else why it could not take effect (torch was
    already imported in this process).
    """
    if WAIT_POLICY_VARIABLE in environ:
        return ""
    if "torch" in sys.modules:
        return (
            f"torch was imported before {WAIT_POLICY_VARIABLE} could be set: its worker threads spin while they "
            "wait, which slows model calls on a busy computer"
        )
    environ[WAIT_POLICY_VARIABLE] = SLEEPING_WORKERS
    return ""
