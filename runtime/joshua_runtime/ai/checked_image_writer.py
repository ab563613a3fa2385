"""The image datasets' PNG writer: LeRobot's AsyncImageWriter interface, but a failed write is kept, not printed.

LeRobot's own writer prints "Error writing image ..." for each PNG it cannot write (a full disk) and goes
on, so a recorder would keep recording an episode that can no longer be saved. Here the first failure
of any writing thread is kept, and `check()` raises it: the episode writer calls it at every frame and
so stops the episode at the first write that failed. Once failed, the writer takes no more images.
"""

import queue
import threading

import PIL.Image
from lerobot.datasets.image_writer import image_array_to_pil_image


class CheckedImageWriter:
    """Threads writing PNG files from a queue; `save_image`, `wait_until_done` and `stop` as LeRobot's."""

    def __init__(self, threads: int):
        self.failure: BaseException | None = None
        self._queue: queue.Queue = queue.Queue()
        self._threads = [threading.Thread(target=self._work, name="png-writer", daemon=True) for _ in range(threads)]
        for thread in self._threads:
            thread.start()

    def save_image(self, image, fpath, compress_level: int = 1) -> None:
        self.check()
        self._queue.put((image, fpath, compress_level))

    def wait_until_done(self) -> None:
        """Wait for every queued image; raises the first failure."""
        self._queue.join()
        self.check()

    def check(self) -> None:
        """Raise the first failed write, if any."""
        if self.failure is not None:
            raise self.failure

    def stop(self) -> None:
        for _ in self._threads:
            self._queue.put(None)
        for thread in self._threads:
            thread.join()
        self._threads = []

    def _work(self) -> None:
        while (item := self._queue.get()) is not None:
            image, path, compress_level = item
            try:
                if self.failure is None:
                    picture = image if isinstance(image, PIL.Image.Image) else image_array_to_pil_image(image)
                    picture.save(path, compress_level=compress_level)
            except Exception as exc:  # kept for check(), naming the file
                if isinstance(exc, OSError) and exc.filename is None:
                    exc.filename = str(path)
                self.failure = self.failure or exc
            finally:
                self._queue.task_done()
        self._queue.task_done()
