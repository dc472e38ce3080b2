"""OpenCV image windows owned by one thread (imshow from callbacks freezes or crashes),
scaled to a readable width and placed side by side."""
import queue
import threading
from typing import Dict

import cv2
import numpy as np

WINDOW_GAP_PX = 10
POLL_S = 0.1


def window_scale(image_width_px: int, window_width_px: int) -> float:
    """Scale factor that makes an image ``window_width_px`` wide (1 when that is 0)."""
    if window_width_px <= 0 or image_width_px <= 0:
        return 1.0
    return window_width_px / float(image_width_px)


def scaled(image: np.ndarray, scale: float) -> np.ndarray:
    """``image`` resized by ``scale``: smooth when enlarging, area-averaged when shrinking."""
    if scale == 1.0:
        return image
    interpolation = cv2.INTER_LINEAR if scale > 1.0 else cv2.INTER_AREA
    return cv2.resize(image, None, fx=scale, fy=scale, interpolation=interpolation)


class ImageWindows:
    """Shows the newest {window name: BGR or mono8 image} offered, from its own thread."""

    def __init__(self, window_width_px: int):
        self.window_width_px = window_width_px
        self._frames = queue.Queue(maxsize=1)
        self._stop = threading.Event()
        self._placed = {}
        self._thread = threading.Thread(target=self._run, name='image_windows', daemon=True)
        self._thread.start()

    def offer(self, frames: Dict[str, np.ndarray]):
        """Queue a set of frames, dropping a set not shown yet."""
        try:
            self._frames.get_nowait()
        except queue.Empty:
            pass
        self._frames.put_nowait(frames)

    def close(self, timeout_s: float = 2.0):
        self._stop.set()
        self._thread.join(timeout_s)

    def _show(self, name: str, image: np.ndarray):
        shown = scaled(image, window_scale(image.shape[1], self.window_width_px))
        if name not in self._placed:
            cv2.namedWindow(name, cv2.WINDOW_AUTOSIZE | cv2.WINDOW_GUI_NORMAL)
            left_px = sum(width + WINDOW_GAP_PX for width in self._placed.values())
            cv2.moveWindow(name, left_px, 0)
            self._placed[name] = shown.shape[1]
        cv2.imshow(name, shown)

    def _run(self):
        while not self._stop.is_set():
            try:
                frames = self._frames.get(timeout=POLL_S)
            except queue.Empty:
                cv2.waitKey(1)
                continue
            for name, image in frames.items():
                self._show(name, image)
            cv2.waitKey(1)
        cv2.destroyAllWindows()
