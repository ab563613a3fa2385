"""The control plane of a robot on several hosts: each host's agent, its Zenoh link to the others, its local socket."""
