"""LTTng-UST's fork handlers, which a process that forks without exec must call itself."""

import ctypes
import os

SIGSET_BYTES = 128  # glibc's sigset_t on Linux
# The names of before / after in the parent / after in the child: lttng-ust 2.12, then 2.13's.
HOOK_NAMES = (
    ("ust_before_fork", "ust_after_fork_parent", "ust_after_fork_child"),
    ("lttng_ust_before_fork", "lttng_ust_after_fork_parent", "lttng_ust_after_fork_child"),
)


class ForkHooksMissing(Exception):
    """A library has none of LTTng-UST's fork handlers."""


class LttngForkHooks:
    """LTTng-UST (which rcl's tracepoints load) starts two listener threads when loaded; a fork without its
    handlers could copy a lock one of them holds. `before` takes its locks and blocks signals, `after_parent`
    releases them, `after_child` re-creates its state and threads in the child and restores the signals."""

    def __init__(self, library: ctypes.CDLL):
        for names in HOOK_NAMES:
            try:
                self.hooks = [getattr(library, name) for name in names]
                break
            except AttributeError:
                continue
        else:
            raise ForkHooksMissing(f"no fork handlers in {library._name}")
        self.signals = ctypes.create_string_buffer(SIGSET_BYTES)

    def before(self) -> None:
        self.hooks[0](self.signals)

    def after_parent(self) -> None:
        self.hooks[1](self.signals)

    def after_child(self) -> None:
        self.hooks[2](self.signals)


def loaded_libraries() -> list[str]:
    with open("/proc/self/maps") as maps:
        return sorted({line.split()[-1] for line in maps if "/" in line})


def lttng_fork_hooks() -> LttngForkHooks | None:
    """The hooks of the LTTng-UST library this process has loaded, None when it has none."""
    for path in loaded_libraries():
        name = os.path.basename(path)
        if name.startswith("liblttng-ust") and not name.startswith(("liblttng-ust-fork", "liblttng-ust-tracepoint")):
            try:
                library = ctypes.CDLL(path, mode=os.RTLD_NOLOAD | os.RTLD_LAZY)
            except OSError:
                continue
            try:
                return LttngForkHooks(library)
            except ForkHooksMissing:
                continue
    return None
