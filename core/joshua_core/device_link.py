"""What every device node does when its device stops answering; docs/bring-up.md, "When a device stops answering".

A node reports a device that stops answering within DEVICE_REPORT_S: one log line, and an ERROR
status where the node publishes /diagnostics. It then recovers on its own or ends with exit code 3
(NODE_EXIT_DEVICE) so that the supervisor restarts it; it never goes on running mute.
"""

# A device that stops answering is reported within this.
DEVICE_REPORT_S = 2.0
# A streaming device silent this long has stopped: half of DEVICE_REPORT_S, the rest is the node's margin.
DEVICE_SILENCE_S = DEVICE_REPORT_S / 2
