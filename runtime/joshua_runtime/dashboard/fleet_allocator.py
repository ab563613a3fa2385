"""Memory the fleet view frees goes back to the system: under glibc, blocks of LARGE_BLOCK_BYTES and more
are mapped one by one, so a status the roster forgets (up to 64 KiB) is returned whole, not kept in the
heap for reuse. glibc's own threshold grows with use (to 32 MiB), which left the memory of junk behind
after its eviction. Under another C library nothing changes."""

import ctypes
import ctypes.util

M_MMAP_THRESHOLD = -3  # mallopt's parameter number (malloc.h)
LARGE_BLOCK_BYTES = 32 * 1024


def map_large_blocks_alone() -> bool:
    """Ask the C library to map blocks of LARGE_BLOCK_BYTES and more on their own; True when it did."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        return bool(libc.mallopt(M_MMAP_THRESHOLD, LARGE_BLOCK_BYTES))
    except (OSError, AttributeError):
        return False
