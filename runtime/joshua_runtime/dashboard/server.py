"""uvicorn's server, telling the dashboard the moment it is asked to stop."""

import asyncio

import uvicorn


class StoppingAwareServer(uvicorn.Server):
    """A uvicorn server that calls `on_stop()` in its event loop as soon as a SIGINT or SIGTERM asks it to
    stop, before it waits for the requests in progress to finish. Built inside the running loop."""

    def __init__(self, config: uvicorn.Config, on_stop):
        super().__init__(config)
        self.on_stop = on_stop
        self.loop = asyncio.get_running_loop()

    def handle_exit(self, sig, frame) -> None:
        super().handle_exit(sig, frame)
        if not self.loop.is_closed():
            self.loop.call_soon_threadsafe(self.on_stop)
