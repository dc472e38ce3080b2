"""Pinhole camera geometry shared by the simulator (to publish camera_info) and the detector.

Conventions: image pixels (u right, v down), optical frame z forward, x right, y down (REP-103).
"""
import math
from dataclasses import dataclass


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics without distortion (px)."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @property
    def K(self):
        """Row-major 3x3 camera matrix, as in sensor_msgs/CameraInfo."""
        return [self.fx, 0.0, self.cx, 0.0, self.fy, self.cy, 0.0, 0.0, 1.0]

    @property
    def P(self):
        """Row-major 3x4 projection matrix of a monocular camera, as in sensor_msgs/CameraInfo."""
        return [self.fx, 0.0, self.cx, 0.0, 0.0, self.fy, self.cy, 0.0, 0.0, 0.0, 1.0, 0.0]


def intrinsics_from_vertical_fov(width: int, height: int, fov_deg: float) -> CameraIntrinsics:
    """Intrinsics of an OpenGL projection with vertical field of view ``fov_deg``.

    Square pixels: fy = (H/2) / tan(fov/2) and fx = fy; the principal point is the image
    centre in pixel-centre coordinates, ((W-1)/2, (H-1)/2).
    """
    focal_px = (height / 2.0) / math.tan(math.radians(fov_deg) / 2.0)
    return CameraIntrinsics(width, height, focal_px, focal_px, (width - 1) / 2.0, (height - 1) / 2.0)
