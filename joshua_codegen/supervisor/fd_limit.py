"""The open-file limit: raised for the supervisor's own clients, given back to every node before exec."""

import resource

from joshua_codegen.supervisor.common import log

# The soft RLIMIT_NOFILE the supervisor raises itself to (never past the hard limit): room for its control
# clients and every node's pipes. Many programs misbehave with a huge soft limit (they loop over every
# possible descriptor, or pass it to select()), so nodes get the limits the supervisor was started with.
FD_LIMIT_WANTED = 65536
STARTED_FD_LIMIT = resource.getrlimit(resource.RLIMIT_NOFILE)


def raise_fd_limit() -> int:
    """Raise the soft limit toward FD_LIMIT_WANTED, within the hard limit; the soft limit now in force."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    wanted = FD_LIMIT_WANTED if hard == resource.RLIM_INFINITY else min(FD_LIMIT_WANTED, hard)
    if soft != resource.RLIM_INFINITY and soft < wanted:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (wanted, hard))
            soft = wanted
        except (OSError, ValueError) as exc:
            log("supervisor", f"warning: cannot raise the open-file limit from {soft} to {wanted}: {exc}")
    return soft


def restore_fd_limit() -> None:
    """In a node's forked child: the soft limit the supervisor was started with (within today's hard limit)."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    started = STARTED_FD_LIMIT[0]
    if hard != resource.RLIM_INFINITY and (started == resource.RLIM_INFINITY or started > hard):
        started = hard
    if started != soft:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (started, hard))
        except (OSError, ValueError):
            pass
