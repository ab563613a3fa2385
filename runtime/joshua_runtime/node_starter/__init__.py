"""The node starter: one process that imports the robot's Python node types once, then forks each node from there.

The generated supervisor starts it when the robot has Python nodes enough (its node_starter.py) and talks to it
over a SOCK_SEQPACKET socket. The starter sends `ready` once its imports are done. Each request
starts one node: its fields separated by NUL bytes (the entrypoint, the node's cgroup or an empty field, the
supervisor's pid, then the node's environment as NAME=VALUE), with the node's output descriptor attached
when its output is kept. The answer is `pid N` or `error TEXT`. The starter forks a short-lived child that
forks the node and exits, so the node is reparented to the supervisor (a child subreaper) and is its child
as an exec'd node is: reaped, signalled and contained the same way. The starter ends when its socket closes.
"""
