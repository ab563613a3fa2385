"""The bridge's server listener: when a client subscribes to a channel, the topic's kept messages go out."""

from collections.abc import Callable

from foxglove.websocket import ServerListener


class ReplayKeptMessages(ServerListener):
    """Calls `replay(topic)` each time a client subscribes to the channel of `topic`; ignores the rest."""

    def __init__(self, replay: Callable[[str], None]):
        self.replay = replay

    def on_subscribe(self, client, channel) -> None:
        self.replay(channel.topic)
