"""A stop point beside the straight approach, for when the safety layer holds that approach back
before its own stop point (an obstacle beside the last stretch, often one remembered out of the
camera's view or in its blind disc, where no turn can clear it).

The robot may stop at the can from any side: on the circle ``~stop_distance`` from its surface.
It drives straight to the point of that circle nearest the straight line's own
(``STOP_ASIDE_STEP_DEG`` apart, up to a quarter turn around the can) that the safety layer lets
it reach, and keeps that point until it arrives or the way there is blocked.
"""
import math
from typing import Optional

import numpy as np

from can_seeker.control import avoidance
from can_seeker.control.safety_filter import SAFETY_RESERVE_M

STOP_ASIDE_STEP_DEG = 5.0
"""Stop points beside the straight approach are tried this far apart around the can (deg)."""


class StopAside:
    """The chosen stop point, as its direction (rad, odom) from the can's centre; None: none."""

    def __init__(self, config, navigator, tracker):
        self.config = config
        self.navigator = navigator
        self.tracker = tracker
        self.reset()

    def reset(self) -> None:
        self.direction_rad: Optional[float] = None

    @property
    def chosen(self) -> bool:
        return self.direction_rad is not None

    def bearing(self) -> Optional[float]:
        """Bearing (rad, base_link) of the stop point to drive to, or None while the straight
        line reaches its own stop point, or when no point is in reach."""
        config, pose = self.config, self.navigator.pose
        can = np.asarray(self.tracker.can_xy, float)
        ring_m = config.stop_distance + config.robot_radius + config.can_radius
        if self.direction_rad is not None:
            point = can + ring_m * np.array((math.cos(self.direction_rad),
                                             math.sin(self.direction_rad)))
            point_base = avoidance.to_frame(point, pose.x, pose.y, pose.yaw)
            if self._reachable(point_base)[0]:
                return math.atan2(point_base[0, 1], point_base[0, 0])
            self.direction_rad = None
        away = np.array((pose.x, pose.y)) - can
        steps = np.radians(STOP_ASIDE_STEP_DEG) * np.arange(
            1, int(90.0 // STOP_ASIDE_STEP_DEG) + 1)
        around = math.atan2(away[1], away[0]) + np.concatenate(
            ([0.0], np.stack((steps, -steps), axis=1).reshape(-1)))
        points = can + ring_m * np.stack((np.cos(around), np.sin(around)), axis=1)
        points_base = avoidance.to_frame(points, pose.x, pose.y, pose.yaw)
        if self._reachable(points_base[:1])[0]:
            return None
        chosen = np.nonzero(self._reachable(points_base[1:]))[0] + 1
        if len(chosen) == 0:
            return None
        self.direction_rad = float(around[chosen[0]])
        return math.atan2(points_base[chosen[0], 1], points_base[chosen[0], 0])

    def _reachable(self, points_base: np.ndarray) -> np.ndarray:
        """Which stop points (N x 2, base_link) a straight drive reaches, within the stop band,
        before the safety layer stops it."""
        needed_m = (np.linalg.norm(points_base, axis=1) - self.config.distance_tolerance / 2.0
                    + SAFETY_RESERVE_M)
        travel_m = self.navigator.free_travel_toward_m(points_base, self.tracker.can_xy,
                                                       self.config.can_exclusion_radius)
        return travel_m >= needed_m
