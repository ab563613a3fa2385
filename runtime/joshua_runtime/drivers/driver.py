"""Base class of the ROS-free hardware drivers: open/close around a device, usable as a context manager."""


class Driver:
    """A device connection. `open()` raises DeviceError with a clear message when the device is absent."""

    def open(self) -> None:
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self):
        self.open()
        return self

    def __exit__(self, *exc) -> None:
        self.close()
