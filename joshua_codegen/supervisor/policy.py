"""Fixed rules of supervisor.py: restart backoff, named waits, signals and exit codes."""

import signal

# Restart backoff: the first restart waits RESTART_DELAY_INITIAL_S, each next one RESTART_DELAY_FACTOR
# times longer, never more than RESTART_DELAY_CAP_S. A run of RESTART_RESET_AFTER_S or longer counts
# as healthy: the restart count and the delay start over. systemd units and supervisord.conf follow it too.
RESTART_DELAY_INITIAL_S = 0.25
RESTART_DELAY_FACTOR = 2.0
RESTART_DELAY_CAP_S = 30.0
RESTART_RESET_AFTER_S = 60.0
KILL_WAIT_S = 5.0  # after SIGKILL, how long to wait for processes stuck in the kernel before giving up
LEFTOVER_POLL_S = 0.05  # while stopping: how often groups whose leader is gone are checked again
TRACKING_POLL_S = 0.1  # without a cgroup: how often the guard walks /proc for new descendants
STOP_SETTLE_S = 0.01  # without a cgroup: after stopping descendants, the wait for forks in flight
SHM_CLOCK_SLACK_S = 0.05  # file times in /dev/shm use the kernel's coarse clock, a tick behind time.time()
# Fast DDS tests whether a peer's segment is alive by taking its lock for a moment, so a dead node's lock
# may be held by a live peer when its segments are first looked for: they are looked for again after each
# of these pauses (a peer may test it again just as the supervisor looks again).
SHM_RECHECKS_S = (1.0, 2.0, 4.0, 8.0, 16.0)
CGROUP_EMPTY_POLL_S = 0.01  # how often an emptied cgroup is checked before it is removed
READY_TIMEOUT_S = 60.0  # a node not ready (no READY=1) this long after its start is warned about, not stopped
# A stopping node may hold its SIGTERM by asking for more time (EXTEND_TIMEOUT_USEC, see notify.py), up to this
# long after its SIGINT: a bound for a node that keeps asking. The recorder asks while it saves the frames it
# recorded before its dataset writer had loaded LeRobot, a wait it bounds at 120 s itself.
STOP_EXTENSION_MAX_S = 120.0
# A process that starts first (a robot's Discovery Server) is waited for this long to be ready before the
# others start anyway (they keep asking it, so they find each other once it serves).
FIRST_READY_TIMEOUT_S = 10.0
RUNTIME_PROBE_TIMEOUT_S = 20.0  # preflight: how long the node interpreter may take to report its runtime

EXIT_OK, EXIT_ESCALATED, EXIT_USAGE, EXIT_PREFLIGHT, EXIT_CRITICAL, EXIT_NODE_FAILED = 0, 1, 2, 3, 4, 5
EXIT_DATA_LOST = 6  # a node exited with the node code for data lost (see ROBOT["node_exit_codes"])
EXIT_INTERNAL = 70  # the supervisor hit a bug of its own (EX_SOFTWARE): it stopped every node and says so
INTERNAL_ERRORS_MAX = 10  # internal errors after which the supervisor SIGKILLs what is left and exits
EXIT_EXEC_FAILED = 127  # a node's child could not exec its program
EXIT_ORPHANED = 125  # a node's child found the supervisor already gone before exec

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
RESET_IN_CHILD = STOP_SIGNALS + (signal.SIGCHLD, signal.SIGPIPE, signal.SIGXFSZ, signal.SIGQUIT)
# A Python node is exec'd with these blocked: its generated entrypoint unblocks them where a stop ends it with 0.
# One sent while its interpreter starts (importing `site`) would else end in Python's fatal error and code 1.
HELD_FOR_PYTHON = STOP_SIGNALS

# Names the fix: the binaries are built by `make cpp` of the joshuac repository; cpp_bin_dir selects them.
CPP_FALLBACK_WARNING = (
    "warning: C++ binary {binary} is missing or not executable; running the Python entrypoint "
    "(make cpp in the joshuac repository builds the binaries into build/bin; "
    "set cpp_bin_dir in the description to the directory holding them)"
)

# The node starter (node_starter.py): Python nodes are forked from one process that imported their types, when a
# robot has this many of them at least (one node gains little, and would share the starter's memory with none).
STARTER_MIN_NODES = 2
STARTER_READY_TIMEOUT_S = 20.0  # its imports done by then, else every Python node starts its own interpreter
STARTER_REPLY_TIMEOUT_S = 5.0  # a fork through it answers in milliseconds; silence this long means it is stuck
STARTER_STOP_TIMEOUT_S = 1.0  # it ends when its socket closes; after this it is killed
STARTER_STOP_POLL_S = 0.005
STARTER_TITLE_SLACK = 256  # bytes of command line beyond the longest node's, for paths a reload may bring
