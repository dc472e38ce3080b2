"""Input freshness: when each input of the controller last came, and which are missing or stale.

An input counts as stale when it will be older than its timeout by the next command (a command
is executed for one control period, so the zero goes out no later than the timeout).
"""
import math
from typing import Dict, List, NamedTuple, Optional, Sequence


class MissingInput(NamedTuple):
    """An input the controller lacks: its ``name`` ('detection', 'odometry', 'camera_info'
    or a scan topic), the ``problem``, e.g. 'no odometry for 1.20 s (timeout 0.50 s)', 'no scan
    on /scan yet', and whether it is ``overdue``: not just awaited since a reset, within its
    timeout."""

    name: str
    problem: str
    overdue: bool = True


def _missing(name: str, what: str, stamp_s: Optional[float], timeout_s: float, now_s: float,
             reset_s: float) -> MissingInput:
    """An input last seen at ``stamp_s`` (None: not since the reset at ``reset_s``), stale at
    ``now_s``: older than ``timeout_s`` now or by the next command."""
    if stamp_s is None:
        return MissingInput(name, 'no %s yet' % what, now_s - reset_s > timeout_s)
    age_s = now_s - stamp_s
    return MissingInput(name, 'no %s for %.2f s (timeout %.2f s%s)' % (
        what, age_s, timeout_s, ' by the next command' if age_s <= timeout_s else ''))


def problems_text(missing: Sequence[MissingInput]) -> str:
    """The problems of ``missing``, in one line."""
    return '; '.join(item.problem for item in missing)


class InputFreshness:
    """Arrival times of the detection (by its image's stamp), odometry, each scan topic and
    camera_info, since the last :meth:`reset`. ``wander`` needs no detections;
    ``needs_camera_info`` (seeking with obstacle sensing) makes camera_info a sensing input."""

    def __init__(self, config, scan_sources: Sequence[str], wander: bool,
                 camera_info_topic: str):
        self.config = config
        self.scan_sources = tuple(scan_sources)
        self.wander = wander
        self.needs_camera_info = bool(self.scan_sources) and not wander
        self.camera_info_topic = camera_info_topic
        self.reset()

    def reset(self, now_s: float = -math.inf) -> None:
        """Nothing heard since ``now_s``."""
        self.ignore_before_s = now_s
        self.last_image_s: Optional[float] = None
        self.pose_s: Optional[float] = None
        self.scan_s: Dict[str, float] = {}
        self.camera_info_s: Optional[float] = None

    def _fresh(self, stamp_s: Optional[float], timeout_s: float, now_s: float) -> bool:
        return stamp_s is not None and now_s + 1.0 / self.config.rate - stamp_s <= timeout_s

    def is_stale(self, now_s: float) -> bool:
        """True when the last detection's image (in WANDER: the odometry) will be older than
        its timeout before the next control tick."""
        if self.wander:
            return not self._fresh(self.pose_s, self.config.odom_timeout, now_s)
        return not self._fresh(self.last_image_s, self.config.detection_timeout, now_s)

    def missing_inputs(self, now_s: float) -> List[MissingInput]:
        """What keeps the robot from driving: the detection when it is stale and, with obstacle
        sensing (or in WANDER), the sensing inputs that are missing or stale."""
        missing = []
        if not self.wander and self.is_stale(now_s):
            missing.append(_missing('detection', 'detection', self.last_image_s,
                                    self.config.detection_timeout, now_s,
                                    self.ignore_before_s))
        if self.scan_sources or self.wander:
            missing += self.sensing_problems(now_s)
        return missing

    def sensing_problems(self, now_s: float) -> List[MissingInput]:
        """Odometry, the scans of every sensor and (see ``needs_camera_info``) camera_info,
        when missing or stale."""
        config = self.config
        problems = []
        if not self._fresh(self.pose_s, config.odom_timeout, now_s):
            problems.append(_missing('odometry', 'odometry', self.pose_s, config.odom_timeout,
                                     now_s, self.ignore_before_s))
        for source in self.scan_sources:
            if not self._fresh(self.scan_s.get(source), config.scan_timeout, now_s):
                problems.append(_missing(source, 'scan on %s' % source, self.scan_s.get(source),
                                         config.scan_timeout, now_s, self.ignore_before_s))
        if self.needs_camera_info and not self._fresh(self.camera_info_s,
                                                      config.camera_info_timeout, now_s):
            problems.append(_missing('camera_info', 'camera_info on %s' % self.camera_info_topic,
                                     self.camera_info_s, config.camera_info_timeout, now_s,
                                     self.ignore_before_s))
        return problems

    def can_navigate(self, now_s: float) -> bool:
        """True when obstacle sensing is on and odometry and every scan are fresh enough to
        drive on grid paths (and to drive at all)."""
        return bool(self.scan_sources) and not self.sensing_problems(now_s)
