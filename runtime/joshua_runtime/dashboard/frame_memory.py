"""The dashboard process set up for a steady stream of large frames: freed buffers are reused, OpenCV runs inline.

Every camera frame passes through buffers of its full size (DDS's serialized copy, the bytes rclpy
hands over, the converted pixels). glibc's malloc gives such buffers back to the kernel as soon as
they are freed and faults fresh zeroed pages in for the next frame: at 15 fps of 640x480 that page
churn cost more CPU than the JPEG encoding. OpenCV's worker threads, woken for each small conversion
and spinning on sched_yield between, cost more than they save on frames this size.
"""

import ctypes
import ctypes.util

# mallopt(3) parameters (malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
# Buffers up to this size come from the heap, not from mmap (a 1920x1080 rgb8 frame is 6 MiB; glibc's
# ceiling is 32 MiB).
MMAP_THRESHOLD_BYTES = 16 * 1024 * 1024
# Free memory at the top of a heap is handed back to the kernel only beyond this (a few frames' worth).
TRIM_THRESHOLD_BYTES = 64 * 1024 * 1024
OPENCV_THREADS = 1


def keep_frame_buffers() -> bool:
    """Tell malloc to keep freed frame-sized buffers for reuse; False where the C library has no mallopt."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) and mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES))


def set_up_for_frames() -> None:
    """Both settings, for the dashboard's process (they are process-wide)."""
    import cv2

    keep_frame_buffers()
    cv2.setNumThreads(OPENCV_THREADS)
