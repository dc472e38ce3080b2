"""The floor some sensor or the robot's body has observed, on cells of half the obstacle
grid's size, and how long each coarse cell has lain in a scan's blind disc (pure numpy).

The rest is unknown floor, which the safety layer keeps off: a camera looking ahead never saw
what stands beside the robot, and a cell the rays call free may hold the corner of an obstacle
seen edge-on. Design and reasons: docs/design/controller-and-safety.md.
"""
import numpy as np

from can_seeker.control.costmap.grid import OBSERVED_SUBDIVISION, GridGeometry, within
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.control.costmap.scan_rays import ScanRays
from can_seeker.lattice import SCALE, lattice

OBSTACLE_REACH_M = 0.3
"""Unknown floor this near a remembered obstacle cell is never taken for floor by waiting: a
camera that saw one side of an obstacle has not seen how far it goes on (a box's unseen
corner, a round table's far rim)."""


class UnknownFloorLayer:
    """Observed fine cells, and the blind-disc time of every coarse cell."""

    def __init__(self, grid: GridGeometry):
        self.grid = grid
        self.observed = np.zeros((grid.fine_cells,) * 2, bool)
        self.blind_disc_s = np.zeros((grid.cells, grid.cells))

    def clear(self) -> None:
        """Forget all observed floor and blind-disc times."""
        self.observed[:] = False
        self.blind_disc_s[:] = 0.0

    def update(self, rays: ScanRays) -> None:
        """The time since the sensor's previous scan is added to the blind-disc time of the
        cells in its blind disc; the fine cells along each ray from the blind zone's edge on
        (one fine cell short of a hit) and those of the hits are observed."""
        if rays.disc is not None:
            self.blind_disc_s[rays.disc[0]] += np.where(rays.disc[1], rays.elapsed_s, 0.0)
        if rays.empty:
            return
        grid, hits, fractions = self.grid, rays.hits, rays.fractions
        fine_free = ((fractions[None, :] <= (rays.length_um - np.where(hits, grid.fine_um,
                                                                       0))[:, None])
                     & (fractions[None, :] >= rays.clear_um))
        hx, hy, hit_inside = grid.lattice_index(rays.ends_um[hits], grid.fine_um,
                                                grid.fine_cells)
        observed = self.observed.reshape(-1)
        seen_free = rays.fine_cells[fine_free]
        observed[seen_free[seen_free >= 0]] = True
        observed[hx[hit_inside] * grid.fine_cells + hy[hit_inside]] = True

    def mark_disc(self, centre_xy, radius_m: float) -> bool:
        """Count the fine cells whose centres lie within ``radius_m`` of odom point
        ``centre_xy`` as observed free floor (under the robot's body: it stands there); False
        when the disc lies off the grid."""
        grid = self.grid
        centre, radius_um = lattice(centre_xy).reshape(2), int(lattice(radius_m))
        fx, fy = grid.window(centre, radius_um, grid.fine_um, grid.fine_cells)
        if len(fx) == 0 or len(fy) == 0:
            return False
        # the disc's squared distances as a sum of a column and a row (exact integers)
        dx = grid.origin_um + fx * grid.fine_um + grid.fine_um // 2 - centre[0]
        dy = grid.origin_um + fy * grid.fine_um + grid.fine_um // 2 - centre[1]
        self.observed[fx[0]:fx[-1] + 1, fy[0]:fy[-1] + 1] |= (
            (dx * dx)[:, None] + (dy * dy)[None, :] <= radius_um * radius_um)
        return True

    def unknown_points(self, centre_xy, radius_m: float, obstacles: ObstacleLayer,
                       max_blind_disc_s: float, max_blind_s: float) -> np.ndarray:
        """Odom centres (N x 2) of the fine cells within ``radius_m`` of ``centre_xy`` that
        nothing has observed, outside the ``obstacles``' occupied cells, and in cells that
        have been in a scan's blind disc for less than ``max_blind_disc_s`` (no ray can observe
        one from there, so it is taken for floor then) or that lie within
        :data:`OBSTACLE_REACH_M` of an obstacle cell scans have had in their blind zone for
        less than ``max_blind_s``: an obstacle seen from one side goes on into the unknown
        floor next to it, and a robot that waits beside it would otherwise take its unseen
        side for floor."""
        grid = self.grid
        centre, radius_um = lattice(centre_xy).reshape(2), int(lattice(radius_m))
        fx, fy = grid.window(centre, radius_um, grid.fine_um, grid.fine_cells)
        if len(fx) == 0 or len(fy) == 0:
            return np.zeros((0, 2))
        # the window's rows and columns as index arrays that broadcast to its cells
        gx, gy = fx[:, None], fy[None, :]
        cx, cy = gx // OBSERVED_SUBDIVISION, gy // OBSERVED_SUBDIVISION
        waiting = self.blind_disc_s[cx, cy] < max_blind_disc_s
        if not waiting.all():
            waiting |= obstacles.near_recent(*np.broadcast_arrays(cx, cy), OBSTACLE_REACH_M,
                                             max_blind_s)
        unknown = ~self.observed[gx, gy] & ~obstacles.occupied_at(cx, cy) & waiting
        ux, uy = np.nonzero(unknown)
        points = grid.centres_um(fx[ux], fy[uy], grid.fine_um).reshape(-1, 2)
        return points[within(points, centre, radius_um)] / SCALE

    def observed_cells(self) -> np.ndarray:
        """Coarse cells some part of which has been observed."""
        fine, cells = OBSERVED_SUBDIVISION, self.grid.cells
        return self.observed.reshape(cells, fine, cells, fine).any(axis=(1, 3))
