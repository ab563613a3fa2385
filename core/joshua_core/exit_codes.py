"""Exit codes of node processes: the runtime ends with them, supervisor.py acts on them."""

NODE_EXIT_OK = 0  # stopped cleanly
NODE_EXIT_FAILURE = 1  # a failure at run time; a restart may help
NODE_EXIT_SETTINGS = 2  # unusable settings (bad model path, unknown registry:NAME, ...): a restart cannot help
NODE_EXIT_DEVICE = 3  # a device is missing, cannot be opened, or stopped answering (see joshua_core.device_link)
NODE_EXIT_DATA_LOST = 6  # data the node had taken in could not be saved (e.g. an episode on a full disk)
