"""Which detection is the can, and where the can is: placed in odom from the pose at the image's
stamp, its gap and bearing then taken from the pose now, carried by odometry while the camera
cannot range it (below the view, or out of view on purpose).
"""
import math
from typing import Optional, Tuple

from can_seeker.control.navigation import CameraView, Pose2D
from can_seeker.control.pose_history import PoseHistory, sighting_from
from can_seeker.control.sighting import Sighting, detection_shows_can

BELOW_VIEW_MARGIN_M = 0.05
"""The can counts as below the view from this far beyond the floor of the image's bottom row
(m): there its base touches the bottom edge, where the floor range gives way to the width
range, with a confidence that falls toward 0 as the silhouette is cut."""


class CanTracker:
    """The can's ``sighting`` (relative to base_link, now), its centre ``can_xy`` in odom where
    it was ranged last, ``ranged_s`` when the camera itself ranged it last (its image's stamp;
    a carried estimate does not count), and ``turn_sign``: the side it was seen on last (left
    at the start)."""

    def __init__(self, config, navigator):
        self.config = config
        self.navigator = navigator
        self.reset()

    @property
    def pose(self) -> Optional[Pose2D]:
        """The robot's latest pose in odom (the navigator's)."""
        return self.navigator.pose

    def reset(self) -> None:
        """No can seen, no poses kept."""
        self.sighting: Optional[Sighting] = None
        self.can_xy: Optional[Tuple[float, float]] = None
        self.ranged_s = -math.inf
        self.turn_sign = 1.0
        self.poses = PoseHistory()

    def observe_pose(self, pose: Pose2D, stamp_s: float) -> None:
        """The robot at ``pose`` (odom; the navigator has it already) at ``stamp_s``: the
        can's gap and bearing follow."""
        self.poses.add(stamp_s, pose)
        if self.sighting is not None and self.sighting.has_range and self.can_xy is not None:
            self.sighting = self.seen_now(self.can_xy, self.sighting.confidence)

    def observe(self, sighting: Optional[Sighting], stamp_s: float, tracking: bool) -> bool:
        """One detection's red object (None: none) of an image taken at ``stamp_s``; with
        ``tracking`` (approaching or stopped at the can) a weaker one near the can still shows
        it (:meth:`shows_can`). Returns whether the can was ranged."""
        can_xy = None if sighting is None else self._can_xy_of(sighting, self.poses.at(stamp_s))
        if sighting is not None and not self.shows_can(sighting, can_xy, tracking):
            sighting, can_xy = None, None
        self.sighting = sighting if can_xy is None else self.seen_now(can_xy,
                                                                      sighting.confidence)
        if sighting is not None and sighting.bearing_rad != 0.0:
            self.turn_sign = math.copysign(1.0, sighting.bearing_rad)
        if can_xy is not None:
            self.can_xy = can_xy
        ranged = sighting is not None and sighting.has_range
        if ranged:
            self.ranged_s = stamp_s
        return ranged

    def carry(self) -> None:
        """Go on with the can where it was ranged last (the camera cannot range it now)."""
        self.sighting = self.seen_now(self.can_xy, self.sighting.confidence
                                      if self.sighting is not None else 0.0)

    def seen_now(self, can_xy: Tuple[float, float], confidence: float) -> Sighting:
        """The can centred at ``can_xy`` (odom) as seen from the latest pose."""
        gap_m, bearing_rad = sighting_from(can_xy, self.pose, self.config.robot_radius,
                                           self.config.can_radius)
        return Sighting(gap_m, bearing_rad, confidence)

    def errors(self) -> Tuple[float, float]:
        """(gap error m, bearing rad) of the current sighting."""
        return self.sighting.gap_m - self.config.stop_distance, self.sighting.bearing_rad

    def gap_to_last_m(self) -> float:
        """The gap to where the can was ranged last (needs ``can_xy`` and a pose)."""
        return self.seen_now(self.can_xy, 0.0).gap_m

    def below_view(self, view: Optional[CameraView]) -> bool:
        """True when the can's near surface is nearer the camera, along its heading, than the
        floor of the image's bottom row plus ``BELOW_VIEW_MARGIN_M``: its base is below the
        image, so the detector cannot range it (or see it at all). False without a can, a pose
        or a camera view that knows its bottom row."""
        pose = self.pose
        if view is None or view.base_near_m <= 0.0 or self.can_xy is None or pose is None:
            return False
        dx, dy = self.can_xy[0] - pose.x, self.can_xy[1] - pose.y
        cos_yaw, sin_yaw = math.cos(pose.yaw), math.sin(pose.yaw)
        can_x = cos_yaw * dx + sin_yaw * dy - view.x
        can_y = -sin_yaw * dx + cos_yaw * dy - view.y
        forward_m = (can_x * math.cos(view.yaw) + can_y * math.sin(view.yaw)
                     - self.config.can_radius)
        return forward_m < view.base_near_m + BELOW_VIEW_MARGIN_M

    def _can_xy_of(self, sighting: Sighting,
                   pose: Optional[Pose2D]) -> Optional[Tuple[float, float]]:
        """Where a ranged sighting from ``pose`` puts the can's centre in odom (None without
        range or pose)."""
        if not sighting.has_range or pose is None:
            return None
        distance = sighting.gap_m + self.config.robot_radius + self.config.can_radius
        return (pose.x + distance * math.cos(pose.yaw + sighting.bearing_rad),
                pose.y + distance * math.sin(pose.yaw + sighting.bearing_rad))

    def shows_can(self, sighting: Sighting, can_xy: Optional[Tuple[float, float]],
                  tracking: bool) -> bool:
        """A red object (placing the can at ``can_xy`` in odom, None if unknown) is the can
        when the detector is MIN_CONFIDENCE sure; while ``tracking``, also down to
        TRACK_CONFIDENCE where it was ranged last (within TRACK_GATE_M): its silhouette close
        up varies from frame to frame."""
        config = self.config
        if detection_shows_can(True, sighting.confidence, config.min_confidence):
            return True
        if (not tracking or self.can_xy is None or can_xy is None
                or not detection_shows_can(True, sighting.confidence, config.track_confidence)):
            return False
        return math.hypot(can_xy[0] - self.can_xy[0],
                          can_xy[1] - self.can_xy[1]) < config.track_gate
