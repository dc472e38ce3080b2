"""Places where the can may stand (see :mod:`can_seeker.control.can_candidates`), each with
whether the camera has had it in view (pure numpy, no ROS)."""
import math
from typing import Callable, List, Optional, Sequence

import numpy as np

from can_seeker.control import avoidance, can_candidates
from can_seeker.control.costmap.grid import GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.lattice import lattice


class CandidateLayer:
    """The remembered places, in odom, in the order they were found."""

    def __init__(self, grid: GridGeometry):
        self.grid = grid
        self.reach_m = can_candidates.MAX_WIDTH_M / 2.0 + grid.resolution_m * math.sqrt(2.0)
        """Remembered obstacle cells reaching this near a place where the can may stand may be
        its own (the scans' returns from the can, each within half the widest run of the place,
        in a cell up to a diagonal across): they do not hide it from the camera. Giving up a
        goal this near gives up the place."""
        self.points: List[np.ndarray] = []
        self.viewed: List[bool] = []

    def clear(self) -> None:
        """Forget every place."""
        self.points = []
        self.viewed = []

    def add(self, points_xy: np.ndarray) -> None:
        """Remember the odom places ``points_xy`` (N x 2), once each (within a cell); one off
        the grid counts as viewed."""
        for point in points_xy:
            if all(np.linalg.norm(point - known) > self.grid.resolution_m
                   for known in self.points):
                self.points.append(point)
                self.viewed.append(self.grid.cell_of(*point) is None)

    def mark_in_view(self, camera_xy: np.ndarray, heading_rad: float, half_fov_rad: float,
                     near_m: float, far_m: float, obstacles: ObstacleLayer) -> None:
        """Count the places in the camera's view from ``camera_xy`` along ``heading_rad`` as
        viewed: within ``half_fov_rad`` of it, from ``near_m`` (a can's top enters the bottom
        row) to ``far_m``, with none of the ``obstacles`` on the line of sight short of
        :attr:`reach_m` from it (compared on the lattice of :mod:`can_seeker.lattice`: a can
        right at the view's edge is in it or not whatever the last bits of the arctan2 that
        place it and the edge)."""
        near_um, far_um = lattice((near_m, far_m))
        for index, point in enumerate(self.points):
            if self.viewed[index]:
                continue
            offset = point - camera_xy
            distance = float(np.hypot(*offset))
            bearing = avoidance.wrap_angle(math.atan2(offset[1], offset[0]) - heading_rad)
            if not (near_um <= lattice(distance) <= far_um
                    and lattice(abs(bearing)) <= lattice(half_fov_rad)):
                continue
            along = np.arange(0.0, max(0.0, distance - self.reach_m),
                              self.grid.resolution_m / 2.0)
            ix, iy, inside = self.grid.index_of(camera_xy + along[:, None] * offset / distance)
            if not bool(obstacles.occupied_at(ix[inside], iy[inside]).any()):
                self.viewed[index] = True

    def is_viewed(self, xy: Sequence[float]) -> bool:
        """True when the camera has had the remembered place ``xy`` in view, or it is no
        remembered place."""
        for point, viewed in zip(self.points, self.viewed):
            if np.array_equal(point, xy):
                return viewed
        return True

    def nearest_unviewed(self, distance_to: Callable) -> Optional[np.ndarray]:
        """The place not yet in view with the least ``distance_to``, or None."""
        waiting = [point for point, viewed in zip(self.points, self.viewed) if not viewed]
        return min(waiting, key=distance_to) if waiting else None

    def give_up_near(self, xy: Sequence[float]) -> None:
        """Count the places within :attr:`reach_m` of odom point ``xy`` as viewed."""
        for index, point in enumerate(self.points):
            if np.linalg.norm(point - np.asarray(xy, float)) <= self.reach_m:
                self.viewed[index] = True
