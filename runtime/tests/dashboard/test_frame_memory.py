"""The dashboard's process keeps freed frame buffers for the next frame and runs OpenCV in the calling thread."""

import subprocess
import sys

import pytest

pytestmark = pytest.mark.process  # the settings are process-wide: they are tried in a Python of their own

# Frames of 640x480 rgb8 copied and freed, three at a time, as the ROS thread does with each camera frame;
# prints the page faults of the copies made once the first round has warmed the heap up.
FRAMES_SCRIPT = """
import resource, sys, threading
import cv2
from joshua_runtime.dashboard.frame_memory import set_up_for_frames
if sys.argv[1] == "set-up":
    set_up_for_frames()
FRAME = bytes(640 * 480 * 3)
ROUNDS, HELD = 50, 3

def faults() -> int:
    def copies():
        return [bytearray(FRAME) for _ in range(HELD)]
    copies()
    before = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt
    for _ in range(ROUNDS):
        copies()
    return resource.getrusage(resource.RUSAGE_THREAD).ru_minflt - before

result = []
thread = threading.Thread(target=lambda: result.append(faults()))
thread.start()
thread.join()
print(result[0], ROUNDS * HELD * len(FRAME) // resource.getpagesize(), cv2.getNumThreads())
"""


def frames_in_a_thread(mode: str) -> tuple[int, int, int]:
    """(page faults, pages copied, OpenCV's threads) of FRAMES_SCRIPT in a fresh Python."""
    done = subprocess.run(
        [sys.executable, "-c", FRAMES_SCRIPT, mode], capture_output=True, text=True, check=True, timeout=60
    )
    faults, pages, threads = map(int, done.stdout.split())
    return faults, pages, threads


def test_frames_copied_over_and_over_reuse_the_freed_pages():
    faults, pages, threads = frames_in_a_thread("set-up")
    assert faults < pages // 100, f"{faults} page faults for {pages} pages copied"
    assert threads == 1


def test_without_the_set_up_the_copies_fault_their_pages_in_again():
    """The check above tells the two apart: malloc's defaults hand each frame's pages back to the kernel."""
    faults, pages, _ = frames_in_a_thread("defaults")
    assert faults > pages // 10
