"""The floor the camera has looked at, on the coarse grid (pure numpy, no ROS)."""
from typing import Tuple

import numpy as np

from can_seeker.control.costmap.grid import RAY_STEPS_PER_CELL, GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.lattice import SCALE, ceil_div, lattice

GIVE_UP_REACH_CELLS = 2
"""Cells either side of an unreachable goal's that count as covered once it is given up."""


class CoverageLayer:
    """Which coarse cells the camera has covered: exploration drives to the rest."""

    def __init__(self, grid: GridGeometry):
        self.grid = grid
        self.seen = np.zeros((grid.cells, grid.cells), bool)

    def clear(self) -> None:
        """Forget where the camera looked."""
        self.seen[:] = False

    def mark_wedge(self, camera_xy, heading_rad: float, half_fov_rad: float, near_m: float,
                   far_m: float, obstacles: ObstacleLayer) -> None:
        """Mark the floor wedge the camera covers: bearings within ``half_fov_rad`` of
        ``heading_rad``, from ``near_m`` to ``far_m`` from ``camera_xy`` (odom), each ray
        stopping at the first of the ``obstacles``' occupied cells."""
        grid = self.grid
        near_um, far_um = int(lattice(near_m)), int(lattice(far_m))
        if far_um <= near_um:
            return
        step_um = grid.resolution_um // RAY_STEPS_PER_CELL
        rays = int(ceil_div(int(lattice(2.0 * half_fov_rad * far_m)), step_um)) + 1
        bearings = heading_rad + np.linspace(-half_fov_rad, half_fov_rad, rays)
        distances_um = np.arange(far_um // step_um + 1) * step_um
        points = (np.asarray(camera_xy, float)[None, None, :]
                  + (distances_um / SCALE)[None, :, None]
                  * np.stack((np.cos(bearings), np.sin(bearings)), axis=-1)[:, None, :])
        ix, iy, inside = grid.index_of(points.reshape(-1, 2))
        blocked = (obstacles.occupied_at(ix, iy) | ~inside).reshape(rays, len(distances_um))
        visible = ~np.maximum.accumulate(blocked, axis=1)
        visible &= distances_um[None, :] >= near_um
        visible = visible.reshape(-1)
        self.seen[ix[visible], iy[visible]] = True

    def cover_around(self, cell: Tuple[int, int]) -> None:
        """Count the cells within :data:`GIVE_UP_REACH_CELLS` of ``cell`` as covered."""
        reach = GIVE_UP_REACH_CELLS
        self.seen[max(0, cell[0] - reach):cell[0] + reach + 1,
                  max(0, cell[1] - reach):cell[1] + reach + 1] = True
