"""A detection's red object relative to base_link: the camera's floor pose, the
:class:`Sighting` (gap from the robot front to the can's near surface, bearing of its centre),
and whether a detection is usable and shows the can.
"""
import math
from dataclasses import dataclass
from typing import Optional

from can_seeker.camera_geometry import CameraPose
from can_seeker.control.navigation import Pose2D


@dataclass(frozen=True)
class Sighting:
    """The can as one detection shows it, relative to base_link.

    ``bearing_rad`` is the direction of the can's centre (left positive); ``gap_m`` is the gap
    between the robot front and the can's near surface, NaN when the detection had no range;
    ``confidence`` is the detector's that the red object is the can (0-1).
    """

    gap_m: float
    bearing_rad: float
    confidence: float = 1.0

    @property
    def has_range(self) -> bool:
        """True when the gap is known, so the controller can drive on it."""
        return math.isfinite(self.gap_m)


def camera_floor_pose(pose: CameraPose) -> Pose2D:
    """The floor-plane part of a camera pose in base_link: where it stands and where it looks."""
    return Pose2D(float(pose.position[0]), float(pose.position[1]), pose.heading_rad)


def detection_problem(found: bool, range_m: float, bearing_rad: float) -> Optional[str]:
    """Why a detection claiming the can was found is malformed, or None when it is usable.

    A NaN range is normal (no usable range in that image) and is not a problem; a found can
    without a finite bearing, or with a negative or infinite range, is.
    """
    if not found:
        return None
    if not math.isfinite(bearing_rad):
        return 'detection has found=true but bearing %r' % (bearing_rad,)
    if math.isinf(range_m) or range_m < 0.0:
        return 'detection has found=true but range %r' % (range_m,)
    return None


def detection_shows_can(found: bool, confidence: float, min_confidence: float) -> bool:
    """Whether a detection is taken as the can: a red object (found) that the detector is
    at least ``min_confidence`` sure is the can (not a red book, flag or toy)."""
    return found and confidence >= min_confidence


def sighting_from_detection(found: bool, range_m: float, bearing_rad: float,
                            camera: Optional[Pose2D],
                            robot_radius: float, can_radius: float,
                            confidence: float = 1.0) -> Optional[Sighting]:
    """The red object of one detection relative to base_link, or None when it shows none.

    A detection without a usable range still tells on which side the object is (the camera's
    bearing has the same sign as base_link's for a camera on the robot's axis). So does one
    whose ``camera`` floor pose is unknown (None: TF has no camera pose): its range cannot be
    placed in base_link, so it has none, and its bearing is taken as base_link's.
    """
    if not found or detection_problem(found, range_m, bearing_rad) is not None:
        return None
    heading = bearing_rad if camera is None else camera.yaw + bearing_rad
    if camera is None or not math.isfinite(range_m):
        return Sighting(math.nan, heading, confidence)
    centre_x = camera.x + (range_m + can_radius) * math.cos(heading)
    centre_y = camera.y + (range_m + can_radius) * math.sin(heading)
    gap_m = math.hypot(centre_x, centre_y) - can_radius - robot_radius
    return Sighting(gap_m, math.atan2(centre_y, centre_x), confidence)
