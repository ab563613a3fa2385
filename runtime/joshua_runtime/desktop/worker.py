"""The link between the panel and a robot: a QObject living on its own thread, reached by queued signals.

A worker polls on a QTimer of its own thread and reports through signals; the window calls its slots
only through signal connections, which Qt queues across threads, so no widget waits on I/O.
"""

from PySide6.QtCore import QMetaObject, QObject, Qt, QThread, QTimer, Signal, Slot

STOP_WAIT_MS = 3000


class LinkWorker(QObject):
    """Base of the serial and ROS workers. Subclasses implement connect_link, poll and the command slots."""

    telemetry = Signal(object)  # model.Telemetry
    connected = Signal(str)  # a one-line description of the link
    failed = Signal(str)  # a one-line error; the worker keeps trying where it can
    message = Signal(str)  # progress worth showing in the status bar
    calibration = Signal(object)  # calibration progress (serial links only)

    direct_bus = False  # True when the link reaches the servos themselves (sensors, calibration, per-joint torque)

    def __init__(self, poll_hz: float):
        super().__init__()
        self.poll_hz = poll_hz
        self._timer: QTimer | None = None

    @Slot()
    def start(self) -> None:
        """Runs on the worker thread: connect, then poll every 1/poll_hz."""
        if not self.connect_link():
            return
        self._timer = QTimer(self)
        self._timer.setInterval(max(1, round(1000 / self.poll_hz)))
        self._timer.timeout.connect(self.poll)
        self._timer.start()

    @Slot()
    def stop(self) -> None:
        if self._timer is not None:
            self._timer.stop()
        self.disconnect_link()

    # --- overridden by the links -------------------------------------------------------------
    def connect_link(self) -> bool:
        raise NotImplementedError

    def disconnect_link(self) -> None:
        raise NotImplementedError

    def poll(self) -> None:
        raise NotImplementedError

    # Command slots (send_goals(dict), set_torque(bool), set_joint_torque(str, bool), estop(),
    # calibrate(str, object)) are defined by each link class only: PySide6 runs a slot that overrides
    # a base-class slot on the emitting thread, which would put bus I/O on the GUI thread.


class LinkThread:
    """Owns the thread a worker runs on; stop() asks the worker to stop there, then joins."""

    def __init__(self, worker: LinkWorker):
        self.worker = worker
        self.thread = QThread()
        self.thread.setObjectName(type(worker).__name__)
        worker.moveToThread(self.thread)
        self.thread.started.connect(worker.start)

    def start(self) -> None:
        self.thread.start()

    def stop(self) -> None:
        if not self.thread.isRunning():
            return
        QMetaObject.invokeMethod(self.worker, "stop", Qt.ConnectionType.BlockingQueuedConnection)
        self.thread.quit()
        self.thread.wait(STOP_WAIT_MS)
