"""Delay and loss on a simulated host's link with netem, where the kernel has it (CONFIG_NET_SCH_NETEM).

Kernels built without sch_netem (some CI machines' are) answer `tc qdisc add ... netem` with
"Specified qdisc kind is unknown". `unavailable_reason(namespace)` probes that once per process, on
the loopback of a namespace of the caller, and says why it is missing; `impair` raises NetemUnavailable
with that reason, so a test that needs delay or loss can tell the machine's limit from a failure.
"""

from testsupport import host_namespaces as ns

PROBE_INTERFACE = "lo"
_probed: dict[str, str] = {}  # "reason" -> "" when netem works, else why not


class NetemUnavailable(RuntimeError):
    """This kernel cannot delay or drop packets with netem."""


def unavailable_reason(namespace: str) -> str:
    """Empty when netem works here, else why not (probed once per process with a throwaway qdisc in `namespace`)."""
    if "reason" not in _probed:
        added = ns.run("tc", "-n", namespace, "qdisc", "add", "dev", PROBE_INTERFACE, "root", "netem", "delay", "1ms",
                       check=False)  # fmt: skip
        if added.returncode == 0:
            ns.run("tc", "-n", namespace, "qdisc", "del", "dev", PROBE_INTERFACE, "root", check=False)
            _probed["reason"] = ""
        else:
            _probed["reason"] = (
                f"this kernel has no netem queueing discipline (CONFIG_NET_SCH_NETEM; `tc qdisc add ... netem` said: "
                f"{added.stderr.strip()}): delay and loss cannot be emulated"
            )
    return _probed["reason"]


def impair(probe_namespace: str, namespace: str, interface: str, delay_ms: float, loss_percent: float) -> None:
    """Delay by `delay_ms` and drop `loss_percent` % of what `interface` in `namespace` sends (0, 0: remove)."""
    reason = unavailable_reason(probe_namespace)
    if reason:
        raise NetemUnavailable(reason)
    if delay_ms == 0 and loss_percent == 0:
        ns.run("tc", "-n", namespace, "qdisc", "del", "dev", interface, "root", check=False)
        return
    ns.run("tc", "-n", namespace, "qdisc", "replace", "dev", interface, "root", "netem",
           "delay", f"{delay_ms}ms", "loss", f"{loss_percent}%")  # fmt: skip
