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
