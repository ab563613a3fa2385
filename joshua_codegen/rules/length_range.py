"""The check shared by the base's length and time fields (E410, E411, E413): finite, above 0, at most a limit."""

import math


def out_of_range(node, field: str, maximum: float, unit: str) -> str | None:
    """The message for a written field outside (0, maximum]; None when it is unset or fits."""
    if not node.HasField(field):
        return None
    value = getattr(node, field)
    if math.isfinite(value) and 0 < value <= maximum:
        return None
    return f"{field} must be above 0 and at most {maximum:g} {unit}, got {value:g}"
