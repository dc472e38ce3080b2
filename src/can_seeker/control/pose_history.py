"""Recent odometry poses by stamp: where the robot was when an image was taken.

A camera frame arrives tens of milliseconds after it was taken, and the robot has moved since;
the can an image shows is placed in odom from the pose at the image's stamp, and the controller
then measures the gap and bearing from where the robot is now.
"""
import bisect
import math
from typing import List, Optional, Tuple

from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.navigation import Pose2D

HISTORY_S = 2.0
"""How far back poses are kept (s): longer than any camera latency worth driving on."""


class PoseHistory:
    """Poses of base_link in odom by stamp (s), the last :data:`HISTORY_S` of them."""

    def __init__(self, span_s: float = HISTORY_S):
        self.span_s = span_s
        self._stamps: List[float] = []
        self._poses: List[Pose2D] = []

    def clear(self) -> None:
        """Forget every pose (after a reset)."""
        self._stamps.clear()
        self._poses.clear()

    def add(self, stamp_s: float, pose: Pose2D) -> None:
        """A pose at ``stamp_s``; one older than the newest is dropped (odometry comes in
        stamp order)."""
        if self._stamps and stamp_s < self._stamps[-1]:
            return
        self._stamps.append(stamp_s)
        self._poses.append(pose)
        first = bisect.bisect_left(self._stamps, stamp_s - self.span_s)
        if first > 0:
            del self._stamps[:first]
            del self._poses[:first]

    def at(self, stamp_s: float) -> Optional[Pose2D]:
        """The pose at ``stamp_s``, interpolated between the poses around it (the oldest kept
        before them, the newest after them); None when there is none."""
        if not self._stamps:
            return None
        index = bisect.bisect_left(self._stamps, stamp_s)
        if index == 0:
            return self._poses[0]
        if index == len(self._stamps):
            return self._poses[-1]
        before_s, after_s = self._stamps[index - 1], self._stamps[index]
        before, after = self._poses[index - 1], self._poses[index]
        span_s = elapsed_s(after_s, before_s)
        weight = elapsed_s(stamp_s, before_s) / span_s if span_s > 0.0 else 1.0
        turn = math.atan2(math.sin(after.yaw - before.yaw), math.cos(after.yaw - before.yaw))
        return Pose2D(before.x + weight * (after.x - before.x),
                      before.y + weight * (after.y - before.y),
                      math.atan2(math.sin(before.yaw + weight * turn),
                                 math.cos(before.yaw + weight * turn)))


def sighting_from(can_xy: Tuple[float, float], pose: Pose2D, robot_radius_m: float,
                  can_radius_m: float) -> Tuple[float, float]:
    """(gap m, bearing rad) of a can centred at ``can_xy`` (odom) seen from ``pose``: the gap
    between the robot front and the can's near surface, the bearing of its centre (left
    positive)."""
    dx, dy = can_xy[0] - pose.x, can_xy[1] - pose.y
    forward = math.cos(pose.yaw) * dx + math.sin(pose.yaw) * dy
    left = -math.sin(pose.yaw) * dx + math.cos(pose.yaw) * dy
    return math.hypot(forward, left) - robot_radius_m - can_radius_m, math.atan2(left, forward)
