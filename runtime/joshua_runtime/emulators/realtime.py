"""Real-time scheduling for an emulator's serving thread, which stands for hardware that answers in microseconds."""

import os

SERVING_PRIORITY = 1  # lowest SCHED_FIFO level: ahead of every normal thread, behind the kernel's own


def raise_to_realtime_priority() -> None:
    """Schedule the calling thread as SCHED_FIFO (Linux applies it to the thread alone), if permitted."""
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO | os.SCHED_RESET_ON_FORK, os.sched_param(SERVING_PRIORITY))
    except (AttributeError, OSError):
        pass  # no CAP_SYS_NICE: normal priority
