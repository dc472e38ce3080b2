"""Lockstep input ordering for the controller: the same inputs, in the same order, every run.

In lockstep the simulator waits for the controller's answer to each camera frame. The answer
must depend only on the frame's sim time, never on which message a busy machine happened to
deliver first: a scan is applied once the odometry has reached its stamp (it is placed at the
pose it was taken from), odometry once every scan taken before it arrived, and a detection is
answered once the odometry has reached its stamp and every live scan source has delivered every
scan due by it. Everything is released in stamp order.

Scan sources run at their own rates: a scan's ``period_s`` (LaserScan ``scan_time``) says when
the source's next scan is due, so a frame waits only for the scans stamped at or before it (a
10 Hz lidar beside 15 Hz frames: two frames in three are answered with the lidar's previous
scan). A source with no period (0: a camera scan, one per frame, stamped like the frame) is due
at every frame. A source's messages arrive in order on one connection, so its newest stamp
says which of its scans have arrived; a source not heard from yet (no schedule known) is not
waited for.

A late frame (camera latency: captured at its stamp, published later) is answered from where
the robot is when it is published: the simulator says when (a delivery: the frame's stamp and
its publication time), and the frame then waits for the odometry of that time and for the
scans due by it, and is released after them. Without a delivery, which odometry had arrived by
the time the frame did would decide the answer. A frame waits for its delivery only once a
delivery was heard of (a simulator that sends none is not waited for).

Nothing waits for ever: when a detection of a later frame arrives while a frame still waits,
the simulator has stepped on without the answer (it timed out), so that frame and everything
stamped up to it is released.
"""
import math
from typing import Any, Callable, Dict, List, Optional, Tuple

STAMP_TOLERANCE_S = 1e-6
_ORDER = {'pose': 0, 'scan': 1, 'detection': 2}


def _stamp_key(stamp_s: float) -> int:
    """A stamp (s) as whole microseconds: a frame's stamp and its delivery's ``time_ref`` are
    the same ROS time, but floats of it may differ in the last bit."""
    return int(round(stamp_s / STAMP_TOLERANCE_S))


class FrameInputs:
    """Pending odometry, scans and detections, released when a frame has all it needs.

    ``pose_live()`` and ``scan_live(source)`` say whether odometry and a scan source have a
    publisher at all (an input without one is not waited for); ``scan_sources`` names the scan
    sources a frame waits for.
    """

    def __init__(self, pose_live: Callable[[], bool], scan_live: Callable[[str], bool],
                 scan_sources=()):
        self._pose_live = pose_live
        self._scan_live = scan_live
        self._scan_sources = tuple(scan_sources)
        self._pending: List[Tuple[float, str, Any]] = []
        self._reset_s = -math.inf
        self._newest_pose_s = -math.inf
        self._newest_detection_s = -math.inf
        self._newest_scan_s: Dict[str, float] = {}
        self._scan_period_s: Dict[str, float] = {}
        self._delivered_s: Dict[int, float] = {}
        self._deliveries_heard = False

    def pose(self, value: Any, stamp_s: float) -> None:
        """Odometry stamped ``stamp_s``."""
        if self._add('pose', value, stamp_s):
            self._newest_pose_s = max(self._newest_pose_s, stamp_s)

    def scan(self, source: str, value: Any, stamp_s: float, period_s: float = 0.0) -> None:
        """A scan of ``source`` stamped ``stamp_s``, whose next scan is due ``period_s`` later
        (0: at every frame)."""
        if self._add('scan', (source, value), stamp_s):
            self._newest_scan_s[source] = max(self._newest_scan_s.get(source, -math.inf),
                                              stamp_s)
            self._scan_period_s[source] = max(0.0, period_s)

    def delivery(self, frame_stamp_s: float, delivered_s: float) -> None:
        """The frame stamped ``frame_stamp_s`` was published at ``delivered_s``."""
        self._deliveries_heard = True
        if frame_stamp_s > self._reset_s + STAMP_TOLERANCE_S:
            self._delivered_s[_stamp_key(frame_stamp_s)] = delivered_s

    def detection(self, value: Any, stamp_s: float) -> None:
        """A detection of the frame stamped ``stamp_s``."""
        if self._add('detection', value, stamp_s):
            self._newest_detection_s = max(self._newest_detection_s, stamp_s)

    def clear(self, reset_s: float = -math.inf) -> None:
        """A reset at sim time ``reset_s``: drop everything pending, and every input stamped at
        or before it that is still on its way (it shows the world before the reset; when it
        arrives depends on the machine's load). Scan sources count their periods from the
        reset (the simulator restarts its schedules there)."""
        self._pending = []
        self._delivered_s = {}
        self._reset_s = reset_s
        for source in self._newest_scan_s:
            self._newest_scan_s[source] = reset_s

    def _add(self, kind: str, value: Any, stamp_s: float) -> bool:
        if stamp_s <= self._reset_s + STAMP_TOLERANCE_S:
            return False
        self._pending.append((stamp_s, kind, value))
        return True

    def _pose_reached(self, stamp_s: float) -> bool:
        return self._newest_pose_s >= stamp_s - STAMP_TOLERANCE_S or not self._pose_live()

    def _due_s(self, kind: str, stamp_s: float) -> float:
        """When an input is applied: a frame at its delivery (its stamp while the delivery is
        unknown), anything else at its stamp."""
        if kind == 'detection':
            return self._delivered_s.get(_stamp_key(stamp_s), stamp_s)
        return stamp_s

    def _release_order(self, item: Tuple[float, str, Any]) -> Tuple[float, int, str]:
        """When applied, then odometry before scans before a detection, then scans by
        source."""
        stamp_s, kind, value = item
        return self._due_s(kind, stamp_s), _ORDER[kind], value[0] if kind == 'scan' else ''

    def _owes_scan(self, source: str, stamp_s: float, at_stamp: bool,
                   due_s: Optional[float] = None) -> bool:
        """Whether live ``source`` still owes a scan stamped before ``stamp_s`` (or at it,
        with ``at_stamp``: a frame, which also waits for periodic scans due by its delivery
        ``due_s``). A source not heard from yet has no schedule to wait for; one without a
        period owes a scan at every frame, and only frames wait for it."""
        if source not in self._newest_scan_s:
            return False
        newest_s = self._newest_scan_s[source]
        period_s = self._scan_period_s[source]
        if at_stamp:
            if period_s == 0.0:
                owes = newest_s < stamp_s - STAMP_TOLERANCE_S
            else:
                due_s = stamp_s if due_s is None else due_s
                owes = (newest_s < due_s - STAMP_TOLERANCE_S
                        and newest_s + period_s <= due_s + STAMP_TOLERANCE_S)
        else:
            owes = period_s > 0.0 and newest_s + period_s < stamp_s - STAMP_TOLERANCE_S
        return owes and self._scan_live(source)

    def _releasable(self, kind: str, stamp_s: float) -> bool:
        """Odometry once every scan taken before it arrived (a scan is placed at the pose
        before it); a scan once the odometry reached it; a frame once its delivery is known
        (when deliveries are sent), the odometry reached the delivery and every scan due by
        it arrived."""
        if kind == 'pose':
            return not any(self._owes_scan(source, stamp_s, False)
                           for source in self._scan_sources)
        if kind == 'scan':
            return self._pose_reached(stamp_s)
        if self._deliveries_heard and _stamp_key(stamp_s) not in self._delivered_s:
            return False
        due_s = self._due_s(kind, stamp_s)
        if not self._pose_reached(due_s):
            return False
        return not any(self._owes_scan(source, stamp_s, True, due_s)
                       for source in self._scan_sources)

    def _given_up_until_s(self) -> float:
        """The stamp up to which inputs are released whatever they wait for: the newest pending
        frame older than a detection that arrived (the simulator stepped on without it)."""
        given_up = [stamp_s for stamp_s, kind, _ in self._pending if kind == 'detection'
                    and stamp_s < self._newest_detection_s - STAMP_TOLERANCE_S]
        return max(given_up, default=-math.inf)

    def ready(self) -> List[Tuple[str, float, Any]]:
        """Take the (kind, stamp s, value) of the inputs that can be applied now, in stamp order
        (odometry before a scan before a detection of the same stamp); a scan's value is
        (source, value). An input waits while an earlier one waits, so the order never depends
        on arrival."""
        self._pending.sort(key=self._release_order)
        given_up_until_s = self._given_up_until_s()
        released = []
        for stamp_s, kind, value in self._pending:
            if not (stamp_s <= given_up_until_s + STAMP_TOLERANCE_S
                    or self._releasable(kind, stamp_s)):
                break
            released.append((kind, stamp_s, value))
            if kind == 'detection':
                self._forget_deliveries_until(stamp_s)
        del self._pending[:len(released)]
        return released

    def _forget_deliveries_until(self, stamp_s: float) -> None:
        """Drop the deliveries of frames stamped up to ``stamp_s`` (answered, or never to be:
        frames whose detection did not come)."""
        last = _stamp_key(stamp_s)
        self._delivered_s = {key: due_s for key, due_s in self._delivered_s.items()
                             if key > last}
