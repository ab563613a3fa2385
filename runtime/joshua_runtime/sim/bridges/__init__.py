"""One simulation bridge per module, each standing in for one hardware node type (named by its registry
entry's sim_bridge) on that node's own topics, message types and QoS; sim/bridge.py says what a bridge is."""
