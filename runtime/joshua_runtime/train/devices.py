"""Where training runs: `--device auto|cpu|cuda|mps`, `auto` taking the first of cuda, mps, cpu this machine has."""

from joshua_runtime.errors import SettingsError

DEVICES = ("auto", "cpu", "cuda", "mps")
AUTO_ORDER = ("cuda", "mps", "cpu")


def available(device: str) -> bool:
    import torch

    if device == "cuda":
        return torch.cuda.is_available()
    if device == "mps":
        return torch.backends.mps.is_available()
    return device == "cpu"


def training_device(name: str) -> str:
    """The torch device type for `name`; a SettingsError when it is unknown or absent here."""
    if name not in DEVICES:
        raise SettingsError(f"unknown device {name!r} (known: {', '.join(DEVICES)})")
    if name == "auto":
        return next(device for device in AUTO_ORDER if available(device))
    if not available(name):
        raise SettingsError(f"device {name!r} requested but this machine has none (use --device auto or cpu)")
    return name
