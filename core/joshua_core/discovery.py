"""Facts of the Fast DDS Discovery Server a robot on several hosts runs: its process, port and GUID prefix.

The compiler plans the server as a process of the server host's supervisor and names it in every
process's DDS profile; the runtime (`python -m joshua_runtime.discovery.supervised`) starts it.
"""

PROCESS_NAME = "discovery_server"  # the process `discovery { }` adds on its server host (a reserved node name)
PROCESS_TYPE = "DISCOVERY_SERVER"
# The runtime's module the process runs: the server as a supervised node (READY=1 once it serves).
RUNTIME_MODULE = "joshua_runtime.discovery.supervised"
DEFAULT_PORT = 11811  # Fast DDS's own default for a Discovery Server
SERVER_ID = 0  # `fast-discovery-server -i 0`: one server per robot
# GUID prefix of `fast-discovery-server -i ID` (Fast DDS 2.x): these bytes with byte 2 set to ID.
_SERVER_PREFIX = (0x44, 0x53, 0x00, 0x5F, 0x45, 0x50, 0x52, 0x4F, 0x53, 0x49, 0x4D, 0x41)


def server_prefix(server_id: int = SERVER_ID) -> str:
    """The server's GUID prefix as Fast DDS XML writes it: twelve dotted hex bytes."""
    prefix = list(_SERVER_PREFIX)
    prefix[2] = server_id
    return ".".join(f"{byte:02x}" for byte in prefix)
