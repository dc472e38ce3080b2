"""The image_converter's parameters and its per-frame answer: blob + camera geometry -> report.

Shared by the ROS node and the offline bag tool so both give the same numbers.
"""
import math
from dataclasses import dataclass
from typing import Optional

from can_seeker.camera_geometry import CameraPose, camera_pose_from_mount, can_range_bearing
from can_seeker.camera_mount import CameraMount
from can_seeker.params import Param
from can_seeker.vision.detector import DETECTOR_PARAMS, Blob

PARAMS = DETECTOR_PARAMS + (
    Param('base_frame', 'base_link', 'frame on the floor (z up) in which the camera pose is '
          'looked up in TF for range and bearing'),
    Param('camera_height', 0.25, 'fallback height of camera_link above the floor when TF has no '
          'camera pose (m); 0 = unknown: range and bearing are NaN without TF', 0.0, 5.0),
    Param('camera_pitch_deg', 25.0, 'fallback camera pitch below the horizon when TF has no '
          'camera pose (deg, positive down)', -89.0, 89.0),
    Param('can_diameter', 0.066, 'diameter of the can, for the near surface and the width '
          'fallback range (m)', 0.001, 1.0),
    Param('show', False, 'open OpenCV windows (origin, result, edges); only when the display '
          'can be opened, headless with a warning otherwise'),
    Param('window_width', 640, 'width of each ~show window (px): images are scaled to it, '
          'keeping their aspect ratio; 0 = image size', 0, 4096),
)


def fallback_pose(camera_height_m: float, camera_pitch_deg: float) -> Optional[CameraPose]:
    """Camera pose from the mount parameters, or None when the height is 0 (unknown)."""
    if camera_height_m <= 0.0:
        return None
    return camera_pose_from_mount(CameraMount(camera_height_m, camera_pitch_deg))


@dataclass(frozen=True)
class CanReport:
    """What one frame says about the can: the fields of can_seeker/CanDetection.

    Pixel values are 0 when not found; range (m) and bearing (rad, left positive) are NaN when
    not found or when the camera geometry is unknown. ``range_method`` is 'floor', 'width' or
    'none' (see camera_geometry.can_range_bearing).
    """

    found: bool
    centroid_x: float
    centroid_y: float
    area: float
    bbox: tuple
    image_width: int
    image_height: int
    range_m: float
    bearing_rad: float
    range_method: str


def can_report(blob: Optional[Blob], image_width: int, image_height: int, pose, intrinsics,
               can_diameter_m: float) -> CanReport:
    """Report of a frame's largest red blob (None: not found) seen with this camera geometry."""
    if blob is None:
        return CanReport(False, 0.0, 0.0, 0.0, (0, 0, 0, 0), image_width, image_height,
                         math.nan, math.nan, 'none')
    bbox = (blob.x, blob.y, blob.width, blob.height)
    range_m, bearing, method = can_range_bearing(
        pose, intrinsics, (blob.centroid_x, blob.centroid_y), bbox, can_diameter_m)
    return CanReport(True, blob.centroid_x, blob.centroid_y, blob.area, bbox, image_width,
                     image_height, range_m, bearing, method)
