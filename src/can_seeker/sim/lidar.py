"""A planar 360-degree lidar on the robot: its beams as rays and their hits as LaserScan ranges.

The sensor frame (the simulator's ``~lidar_frame``, ``base_scan`` by default) sits ``height_m``
above base_link with the same axes; beam i points at angle_min + i * angle_increment about z,
counter-clockwise from x (REP-103), the field centred on x (a full circle starts at -pi). Ranges follow REP-117: a beam that hits
nothing within range_max reads +inf.
"""
import math
from dataclasses import dataclass
from typing import Tuple

import numpy as np


@dataclass(frozen=True)
class LidarSpec:
    """Beam count, range limits (m), mounting height over base_link (m) and field of view
    (deg)."""

    beams: int = 360
    range_min_m: float = 0.12
    range_max_m: float = 8.0
    height_m: float = 0.1
    field_deg: float = 360.0

    @property
    def angle_min_rad(self) -> float:
        """Angle of the first beam (rad)."""
        return -math.radians(self.field_deg) / 2.0

    @property
    def angle_increment_rad(self) -> float:
        """Angle between neighbouring beams (rad): a full circle has no beam at +pi, a narrower
        field has beams at both edges."""
        if self.field_deg >= 360.0 or self.beams < 2:
            return math.radians(self.field_deg) / self.beams
        return math.radians(self.field_deg) / (self.beams - 1)

    @property
    def angle_max_rad(self) -> float:
        """Angle of the last beam (rad)."""
        return self.angle_min_rad + (self.beams - 1) * self.angle_increment_rad

    def angles_rad(self) -> np.ndarray:
        """Every beam's angle in the sensor frame (rad)."""
        return self.angle_min_rad + self.angle_increment_rad * np.arange(self.beams)

    def rays(self, x_m: float, y_m: float, yaw_rad: float) -> Tuple[np.ndarray, np.ndarray]:
        """(starts, ends), N x 3 world points (m), of the beams of a lidar on a robot at (x, y)
        heading ``yaw_rad``: each beam from range_min to range_max."""
        world_angles = yaw_rad + self.angles_rad()
        directions = np.stack([np.cos(world_angles), np.sin(world_angles),
                               np.zeros(self.beams)], axis=1)
        origin = np.array((x_m, y_m, self.height_m))
        return origin + self.range_min_m * directions, origin + self.range_max_m * directions

    def ranges(self, hit_fractions: np.ndarray) -> np.ndarray:
        """Ranges (m, float32) from the hit fraction of each ray (1 or more: no hit -> inf)."""
        fractions = np.asarray(hit_fractions, dtype=float)
        ranges = self.range_min_m + fractions * (self.range_max_m - self.range_min_m)
        return np.where(fractions < 1.0, ranges, np.inf).astype(np.float32)
