"""sensor_msgs/LaserScan ranges as rays in the scan's frame (REP-117 conventions).

A finite range within [range_min, range_max] is a return; +inf (or a finite range beyond
range_max) means nothing within range_max, so the floor is free up to range_max along that ray;
NaN, -inf and ranges below range_min say nothing and are dropped.
"""
from typing import Sequence, Tuple

import numpy as np


def scan_rays(angle_min_rad: float, angle_increment_rad: float, ranges_m: Sequence[float],
              range_min_m: float, range_max_m: float) -> Tuple[np.ndarray, np.ndarray]:
    """(ends N x 2 in the scan frame's xy plane, hits N) of the rays that say something."""
    ranges = np.asarray(ranges_m, float)
    angles = angle_min_rad + angle_increment_rad * np.arange(len(ranges))
    hits = np.isfinite(ranges) & (ranges >= range_min_m) & (ranges <= range_max_m)
    free = (np.isposinf(ranges) | (np.isfinite(ranges) & (ranges > range_max_m)))
    keep = hits | free
    lengths = np.where(hits, ranges, range_max_m)[keep]
    ends = np.stack((lengths * np.cos(angles[keep]), lengths * np.sin(angles[keep])), axis=-1)
    return ends, hits[keep]
