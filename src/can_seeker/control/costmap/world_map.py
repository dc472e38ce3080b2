"""The controller's world model: the map's layers over one odom-frame grid, behind the few
updates and queries the planner, the path follower and the safety layer need (pure numpy).

Updates: a range scan, a camera view, the robot's footprint, a bumper contact, places where
the can may stand. Queries: obstacle cells (grown by a clearance for planning), remembered
obstacle points and unknown floor near the robot, coverage and frontier input, OccupancyGrid
values. Layers: :mod:`obstacle_layer`, :mod:`unknown_floor_layer`, :mod:`coverage_layer`,
:mod:`candidate_layer`. Design and reasons: docs/design/controller-and-safety.md.
"""
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from can_seeker.control.costmap.candidate_layer import CandidateLayer
from can_seeker.control.costmap.coverage_layer import CoverageLayer
from can_seeker.control.costmap.grid import GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.control.costmap.scan_rays import ScanRays
from can_seeker.control.costmap.unknown_floor_layer import UnknownFloorLayer
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.planner import inflate


class WorldMap:
    """What the robot has learnt about a ``size_m`` square centred on the odom origin."""

    def __init__(self, resolution_m: float, size_m: float):
        self.grid = GridGeometry(resolution_m, size_m)
        self.resolution_m = self.grid.resolution_m
        self.origin_m = self.grid.origin_m
        self.observed_resolution_m = self.grid.observed_resolution_m
        self.obstacles = ObstacleLayer(self.grid)
        self.floor = UnknownFloorLayer(self.grid)
        self.coverage = CoverageLayer(self.grid)
        self.candidates = CandidateLayer(self.grid)
        self.scan_s: Dict[str, float] = {}
        """The stamp of each sensor's last scan."""
        self.changes = 0
        """Counts the calls that changed the obstacle and observed layers (scans, contacts,
        the robot's body, clearing): answers derived from them stay valid while it stands."""

    def clear(self) -> None:
        """Forget every obstacle, all observed floor, all coverage and every place."""
        self.changes += 1
        self.obstacles.clear()
        self.floor.clear()
        self.coverage.clear()
        self.candidates.clear()
        self.scan_s = {}

    def cell_of(self, x_m: float, y_m: float) -> Optional[Tuple[int, int]]:
        """The cell holding odom point (x, y), or None outside the grid."""
        return self.grid.cell_of(x_m, y_m)

    def centre_of(self, ix, iy) -> np.ndarray:
        """Odom (x, y) of cell centres (arrays broadcast)."""
        return self.grid.centre_of(ix, iy)

    def index_of(self, xy: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(ix, iy, inside) of odom points ``xy`` (N x 2); indices are clipped where outside."""
        return self.grid.index_of(xy)

    # updates -----------------------------------------------------------------------------

    def update_from_scan(self, origin_xy, ends_xy: np.ndarray, hits: np.ndarray,
                         clear_from_m: float = 0.0, stamp_s: float = 0.0,
                         source: str = '') -> None:
        """Rays from ``origin_xy`` to ``ends_xy`` (N x 2, odom) taken at ``stamp_s`` by sensor
        ``source``, blind nearer than ``clear_from_m``: the floor along each ray is free and
        observed, its end an obstacle where ``hits`` is true (a ray without a return ends at
        the range it can vouch for); what is remembered in the blind zone stays and ages (see
        :meth:`ObstacleLayer.update`, :meth:`UnknownFloorLayer.update`)."""
        self.changes += 1
        previous_s = self.scan_s.get(source)
        elapsed = 0.0 if previous_s is None else elapsed_s(stamp_s, previous_s)
        self.scan_s[source] = stamp_s
        rays = ScanRays(self.grid, origin_xy, ends_xy, hits, clear_from_m, elapsed)
        self.floor.update(rays)
        self.obstacles.update(rays)

    def update_from_camera(self, camera_xy, heading_rad: float, half_fov_rad: float,
                           near_m: float, far_m: float) -> None:
        """The camera at ``camera_xy`` (odom) looked along ``heading_rad``, ``half_fov_rad``
        either side, from ``near_m`` to ``far_m``: it covered that floor wedge up to the
        obstacles, and had the places there in view."""
        self.coverage.mark_wedge(camera_xy, heading_rad, half_fov_rad, near_m, far_m,
                                 self.obstacles)
        self.candidates.mark_in_view(np.asarray(camera_xy), heading_rad, half_fov_rad, near_m,
                                     far_m, self.obstacles)

    def update_from_footprint(self, centre_xy, radius_m: float) -> None:
        """The robot's body (or a sensor's blind disc at the start) covers the floor within
        ``radius_m`` of ``centre_xy``: it is observed free."""
        if self.floor.mark_disc(centre_xy, radius_m):
            self.changes += 1

    def add_contact(self, xy) -> None:
        """The robot touched something at odom point ``xy``: its cell is an obstacle until
        :meth:`clear`."""
        cell = self.cell_of(*xy)
        if cell is None:
            return
        self.changes += 1
        self.obstacles.add_contact(cell, xy)

    def forget_coverage(self) -> None:
        """Forget where the camera looked (obstacles stay)."""
        self.coverage.clear()

    def give_up_at(self, xy: Sequence[float]) -> None:
        """Count the cells about the odom goal ``xy`` as covered and the places near it as
        viewed (it cannot be reached)."""
        cell = self.cell_of(xy[0], xy[1])
        if cell is not None:
            self.coverage.cover_around(cell)
        self.candidates.give_up_near(xy)

    # queries -----------------------------------------------------------------------------

    def occupied(self) -> np.ndarray:
        """Cells with more evidence of an obstacle than of free floor, or a contact."""
        return self.obstacles.occupied_at(slice(None), slice(None))

    def known(self) -> np.ndarray:
        """Cells the camera covered or that hold an obstacle: beyond them nothing is known."""
        return self.coverage.seen | self.occupied()

    def seen_cells(self) -> np.ndarray:
        """The cells the camera has covered (read, do not write)."""
        return self.coverage.seen

    def covered_count(self) -> int:
        """How many cells the camera has covered."""
        return int(np.count_nonzero(self.coverage.seen))

    def is_seen(self, xy: Sequence[float]) -> bool:
        """True when the camera has covered the cell of odom point ``xy`` (or it lies off the
        grid)."""
        cell = self.cell_of(xy[0], xy[1])
        return cell is None or bool(self.coverage.seen[cell])

    def blocked_cells(self, clearance_m: float, exclude_xy=None,
                      exclude_radius_m: float = 0.0) -> np.ndarray:
        """Cells within ``clearance_m`` of an obstacle cell (centre to centre), leaving out
        the obstacle cells whose centres lie within ``exclude_radius_m`` of ``exclude_xy``."""
        occupied = self.occupied()
        if exclude_xy is not None:
            ix, iy = np.nonzero(occupied)
            centres = self.centre_of(ix, iy).reshape(-1, 2)
            near = np.linalg.norm(centres - np.asarray(exclude_xy, float), axis=1) \
                <= exclude_radius_m
            occupied = occupied.copy()
            occupied[ix[near], iy[near]] = False
        return inflate(occupied, clearance_m / self.resolution_m)

    def obstacle_points(self, centre_xy, radius_m: float,
                        max_blind_s: float = np.inf) -> np.ndarray:
        """Odom points (N x 2) of the remembered obstacles within ``radius_m`` of
        ``centre_xy`` (see :meth:`ObstacleLayer.points_near`)."""
        return self.obstacles.points_near(centre_xy, radius_m, max_blind_s)

    def unknown_points(self, centre_xy, radius_m: float, max_blind_disc_s: float = np.inf,
                       max_blind_s: float = np.inf) -> np.ndarray:
        """Odom centres (N x 2) of the unknown fine cells within ``radius_m`` of
        ``centre_xy`` (see :meth:`UnknownFloorLayer.unknown_points`)."""
        return self.floor.unknown_points(centre_xy, radius_m, self.obstacles, max_blind_disc_s,
                                         max_blind_s)

    def _occupancy_data(self, known: np.ndarray) -> np.ndarray:
        """nav_msgs/OccupancyGrid data (rows along y, columns along x, row-major from the origin
        cell): 100 obstacle, 0 on the other ``known`` cells, -1 on the rest."""
        values = np.where(known, 0, -1).astype(np.int8)
        values[self.occupied()] = 100
        return values.T

    def coverage_values(self) -> np.ndarray:
        """The coverage as OccupancyGrid data: 100 obstacle, 0 floor the camera covered, -1 not
        covered."""
        return self._occupancy_data(self.coverage.seen)

    def obstacle_values(self) -> np.ndarray:
        """The obstacle memory as OccupancyGrid data: 100 obstacle, 0 where some ray or the
        robot's body has observed part of the cell, -1 unknown (nothing has seen that floor)."""
        return self._occupancy_data(self.floor.observed_cells())
