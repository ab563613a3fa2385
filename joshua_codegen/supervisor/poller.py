"""The loop's wait: callbacks per readable or writable descriptor, on selectors (epoll), so any fd number works."""

import selectors
import time
from collections.abc import MutableMapping


class Poller:
    """Waits for many descriptors at once. `readers[fd] = callback` runs `callback()` whenever fd is
    readable, `writers[fd] = callback` whenever it is writable; `del` (or `pop`) stops that. epoll has no
    FD_SETSIZE: descriptors above 1023 work, and a wait costs the same with a thousand idle ones.

    A descriptor should leave both mappings before it is closed (the kernel forgets a closed descriptor,
    the selector does not); setting a callback registers its number anew, so a stale entry cannot hide a
    new descriptor of the same number."""

    def __init__(self):
        self.selector = selectors.DefaultSelector()
        self.woke_at = time.monotonic()  # when the last wait returned: the start of the loop's turn
        self.readers = Callbacks(self)
        self.writers = Callbacks(self)

    def update(self, fd: int, fresh: bool = False) -> None:
        """Tell the selector which events of `fd` are wanted now; `fresh`: a callback was just set, so
        register anew (the number may belong to a descriptor closed while still registered)."""
        events = (selectors.EVENT_READ if fd in self.readers else 0) | (
            selectors.EVENT_WRITE if fd in self.writers else 0
        )
        try:
            registered = self.selector.get_key(fd).events
        except KeyError:
            registered = 0
        if events == registered and not fresh:
            return
        if registered:
            try:
                self.selector.unregister(fd)
            except (KeyError, ValueError, OSError):
                pass
        if events:
            self.selector.register(fd, events)

    def wait(self, timeout: float | None) -> None:
        """Sleep until a descriptor is ready or `timeout` seconds pass; run the callbacks of the ready ones.

        A callback may add or remove descriptors: each one is looked up again just before it runs."""
        ready = self.selector.select(timeout)
        self.woke_at = time.monotonic()
        for key, events in ready:
            fd = key.fd
            if events & selectors.EVENT_READ and fd in self.readers:
                self.readers[fd]()
            if events & selectors.EVENT_WRITE and fd in self.writers:
                self.writers[fd]()

    def close(self) -> None:
        self.selector.close()


class Callbacks(MutableMapping):
    """fd -> callback for one kind of event of a Poller; setting or deleting an entry updates the selector."""

    def __init__(self, poller: Poller):
        self.poller = poller
        self.callbacks: dict = {}

    def __getitem__(self, fd):
        return self.callbacks[fd]

    def __setitem__(self, fd, callback):
        self.callbacks[fd] = callback
        self.poller.update(fd, fresh=True)

    def __delitem__(self, fd):
        del self.callbacks[fd]
        self.poller.update(fd)

    def __iter__(self):
        return iter(self.callbacks)

    def __len__(self):
        return len(self.callbacks)

    def __contains__(self, fd):
        return fd in self.callbacks
