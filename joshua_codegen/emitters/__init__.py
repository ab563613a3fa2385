"""Emitters: each turns the model into some of the output files. Order does not matter."""

from joshua_codegen.emitters import entrypoints, fastdds, manifest, supervisor, supervisord, systemd, topology

EMITTERS = [
    manifest.emit,
    topology.emit,
    entrypoints.emit,
    fastdds.emit,
    supervisor.emit,
    systemd.emit,
    supervisord.emit,
]

# What a robot on several hosts writes once for the whole robot (the manifest first: each host's output also
# gets its own; the graph is copied into every host's output as it is).
WHOLE_ROBOT = [manifest.emit, topology.emit]
