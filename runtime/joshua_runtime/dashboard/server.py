"""uvicorn's server, letting its program end by itself after a stop signal, and telling the dashboard of the stop."""

import asyncio
import contextlib

import uvicorn


class SelfEndingServer(uvicorn.Server):
    """A uvicorn server after whose stop the program ends by itself.

    uvicorn raises the signal that stopped it again once it has shut down, so that the process ends as the
    signal's default would: on SIGTERM it then dies by that signal before the program's own last steps (the
    dashboard's fleet status withdrawn and ROS left, the fleet view's Zenoh session closed), and its process
    manager counts a crash. Here the signal is not raised again: `serve()` returns, and the program ends with
    code 0 on either signal."""

    @contextlib.contextmanager
    def capture_signals(self):
        with super().capture_signals():
            try:
                yield
            finally:
                self._captured_signals.clear()  # what uvicorn would raise again as it restores the handlers


class StoppingAwareServer(SelfEndingServer):
    """A SelfEndingServer that calls `on_stop()` in its event loop as soon as a SIGINT or SIGTERM asks it to
    stop, before it waits for the requests in progress to finish. Built inside the running loop."""

    def __init__(self, config: uvicorn.Config, on_stop):
        super().__init__(config)
        self.on_stop = on_stop
        self.loop = asyncio.get_running_loop()

    def handle_exit(self, sig, frame) -> None:
        super().handle_exit(sig, frame)
        if not self.loop.is_closed():
            self.loop.call_soon_threadsafe(self.on_stop)
