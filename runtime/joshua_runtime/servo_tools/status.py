"""`joshua-servo status`: the servos' telemetry (drivers/sts3215_status.py) as a table for a terminal."""

from joshua_runtime.drivers.sts3215_status import ServoStatus


def format_table(statuses: list[ServoStatus]) -> str:
    """A fixed-width table for a terminal."""
    lines = [f"{'id':>3} {'position':>8} {'speed':>6} {'load %':>7} {'volts':>6} {'temp C':>6}  errors"]
    for s in statuses:
        lines.append(
            f"{s.id:>3} {s.position:>8} {s.speed:>6} {s.load_percent:>7.1f} {s.voltage_v:>6.1f} "
            f"{s.temperature_c:>6}  {', '.join(s.errors) or '-'}"
        )
    return "\n".join(lines)
