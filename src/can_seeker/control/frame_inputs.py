"""Lockstep input ordering for the controller: the same inputs, in the same order, every run.

In lockstep the simulator waits for the controller's answer to each camera frame. The answer
must depend only on the frame's sim time, never on which message a busy machine happened to
deliver first: a scan is applied once the odometry has reached its stamp (it is placed at the
pose it was taken from), and a detection is answered once the odometry and, while a scan source
is live, the scan have reached its stamp (or once odometry after the frame shows that the
simulator has stopped waiting for it). Everything is released in stamp order.
"""
from typing import Any, Callable, List, Tuple

STAMP_TOLERANCE_S = 1e-6
_ORDER = {'pose': 0, 'scan': 1, 'detection': 2}


class FrameInputs:
    """Pending odometry, scans and detections, released when a frame has all it needs.

    ``pose_live()`` and ``scan_live()`` say whether those inputs have a source at all (an input
    without one is not waited for).
    """

    def __init__(self, pose_live: Callable[[], bool], scan_live: Callable[[], bool]):
        self._pose_live = pose_live
        self._scan_live = scan_live
        self._pending: List[Tuple[float, str, Any]] = []
        self._reset_s = -float('inf')
        self._newest = {'pose': -float('inf'), 'scan': -float('inf')}

    def pose(self, value: Any, stamp_s: float) -> None:
        """Odometry stamped ``stamp_s``."""
        self._add('pose', value, stamp_s)

    def scan(self, value: Any, stamp_s: float) -> None:
        """A scan stamped ``stamp_s``."""
        self._add('scan', value, stamp_s)

    def detection(self, value: Any, stamp_s: float) -> None:
        """A detection of the frame stamped ``stamp_s``."""
        self._add('detection', value, stamp_s)

    def clear(self, reset_s: float = -float('inf')) -> None:
        """A reset at sim time ``reset_s``: drop everything pending, and every input stamped at
        or before it that is still on its way (it shows the world before the reset; when it
        arrives depends on the machine's load)."""
        self._pending = []
        self._reset_s = reset_s

    def _add(self, kind: str, value: Any, stamp_s: float) -> None:
        if stamp_s <= self._reset_s + STAMP_TOLERANCE_S:
            return
        self._pending.append((stamp_s, kind, value))
        if kind in self._newest:
            self._newest[kind] = max(self._newest[kind], stamp_s)

    def _reached(self, kind: str, stamp_s: float, live: Callable[[], bool]) -> bool:
        return self._newest[kind] >= stamp_s - STAMP_TOLERANCE_S or not live()

    def _releasable(self, kind: str, stamp_s: float) -> bool:
        if kind == 'pose':
            return True
        if not self._reached('pose', stamp_s, self._pose_live):
            return False
        if kind == 'scan' or self._reached('scan', stamp_s, self._scan_live):
            return True
        # Odometry after the frame: the simulator stopped waiting for it (timeout), so its
        # scan is not coming in time either.
        return self._newest['pose'] > stamp_s + STAMP_TOLERANCE_S

    def ready(self) -> List[Tuple[str, float, Any]]:
        """Take the (kind, stamp s, value) of the inputs that can be applied now, in stamp order
        (odometry before a scan before a detection of the same stamp). An input waits while an
        earlier one waits, so the order never depends on arrival."""
        self._pending.sort(key=lambda item: (item[0], _ORDER[item[1]]))
        released = []
        for stamp_s, kind, value in self._pending:
            if not self._releasable(kind, stamp_s):
                break
            released.append((kind, stamp_s, value))
        del self._pending[:len(released)]
        return released
