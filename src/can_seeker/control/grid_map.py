"""What the robot has learnt about the floor, on a coarse grid in the odom frame.

Two layers over the same square cells:

- obstacle evidence from range scans (a hit adds four times what a ray passing through
  subtracts, both clamped), so obstacles stay known while they are out of the sensor's view
  (beside or behind the robot, or in the blind zone nearer than its range_min) or a few frames
  of a scan miss them (a camera sees a tall obstacle's silhouette lean past its base), and a
  moved object is cleared by the rays that keep passing through its old place. Each obstacle
  cell also counts how long scans have had it in their blind zone (nearer than range_min to
  the sensor, along a ray or beside the view) since one last hit it: there no ray can confirm
  or clear it, and no turn of the robot brings it into view, so a phantom there can be told
  apart only by that time. A scan that reports an obstacle right at its range_min (a camera
  whose image's bottom edge cuts an obstacle: it is at most that far) keeps the remembered
  obstacle cells along that ray nearer than range_min: it still sees something there, so they
  are no phantom to drop;
- contacts: cells where the robot's bumper touched something (:meth:`GridMap.add_contact`).
  A contact is an obstacle no scan may clear or forget (the sensors did not see it, so their
  free rays through its place prove nothing) until the map is cleared;
- coverage: the floor the camera has looked at, up to the range at which it would have found
  the can, stopping at obstacles. Exploration drives to where it has not looked yet;
- observed, on cells of half the size: the floor some scan ray has reached (free or hit), the
  robot's body has covered, or the robot started on. The rest is unknown: a camera looking
  ahead never saw what stands beside the robot, and a cell the rays call free may hold the
  corner of an obstacle seen edge-on, so the safety layer treats unknown floor near the robot
  as an obstacle. Half-size cells keep that corner's cell unknown where the coarse cell
  around it was partly seen free. Each coarse cell also counts how long it has been within a
  scan's blind disc (nearer than range_min to the sensor, any bearing): from there no turn of
  the robot can observe it.

Arrays are indexed ``[ix, iy]``; cell (ix, iy) spans ``origin + (ix, iy) * resolution`` to one
resolution further. Odom positions outside the grid are ignored.
"""
import math
from typing import Dict, Optional, Tuple

import numpy as np

from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.planner import inflate

HIT_EVIDENCE = 4
MISS_EVIDENCE = 1
EVIDENCE_LIMIT = 12
OBSERVED_SUBDIVISION = 2
BLIND_EDGE_M = 0.01
"""A return this near to a scan's range_min or nearer lies at the edge of its blind zone (see
:meth:`GridMap.add_scan`)."""
"""Observed floor is kept on cells this many times finer than the obstacle grid's."""
OBSTACLE_REACH_M = 0.3
"""Unknown floor this near a remembered obstacle cell is never taken for floor by waiting: a
camera that saw one side of an obstacle has not seen how far it goes on (a box's unseen
corner, a round table's far rim)."""


class GridMap:
    """Obstacle evidence and camera coverage of a ``size_m`` square centred on the odom origin."""

    def __init__(self, resolution_m: float, size_m: float):
        self.resolution_m = float(resolution_m)
        self.cells = max(1, int(math.ceil(size_m / resolution_m)))
        self.origin_m = -self.cells * self.resolution_m / 2.0
        self.evidence = np.zeros((self.cells, self.cells), np.int16)
        self.seen = np.zeros((self.cells, self.cells), bool)
        self.observed_resolution_m = self.resolution_m / OBSERVED_SUBDIVISION
        self.observed = np.zeros((self.cells * OBSERVED_SUBDIVISION,) * 2, bool)
        self.blind_s = np.zeros((self.cells, self.cells))
        self.blind_disc_s = np.zeros((self.cells, self.cells))
        self.scan_s: Dict[str, float] = {}
        self.hit_xy = np.zeros((self.cells, self.cells, 2))
        self.contact = np.zeros((self.cells, self.cells), bool)

    def clear(self) -> None:
        """Forget every obstacle and all coverage."""
        self.evidence[:] = 0
        self.seen[:] = False
        self.observed[:] = False
        self.blind_s[:] = 0.0
        self.blind_disc_s[:] = 0.0
        self.contact[:] = False
        self.scan_s = {}

    def forget_coverage(self) -> None:
        """Forget where the camera looked (obstacles stay)."""
        self.seen[:] = False

    def index_of(self, xy: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(ix, iy, inside) of odom points ``xy`` (N x 2); indices are clipped where outside."""
        ij = np.floor((np.asarray(xy, float).reshape(-1, 2) - self.origin_m)
                      / self.resolution_m).astype(int)
        inside = np.all((ij >= 0) & (ij < self.cells), axis=1)
        ij = np.clip(ij, 0, self.cells - 1)
        return ij[:, 0], ij[:, 1], inside

    def cell_of(self, x_m: float, y_m: float) -> Optional[Tuple[int, int]]:
        """The cell holding odom point (x, y), or None outside the grid."""
        ix, iy, inside = self.index_of(np.array((x_m, y_m)))
        return (int(ix[0]), int(iy[0])) if inside[0] else None

    def centre_of(self, ix, iy) -> np.ndarray:
        """Odom (x, y) of cell centres (arrays broadcast)."""
        return np.stack((self.origin_m + (np.asarray(ix) + 0.5) * self.resolution_m,
                         self.origin_m + (np.asarray(iy) + 0.5) * self.resolution_m), axis=-1)

    def occupied(self) -> np.ndarray:
        """Cells with more evidence of an obstacle than of free floor, or a contact."""
        return self.occupied_at(slice(None), slice(None))

    def occupied_at(self, ix, iy) -> np.ndarray:
        """:meth:`occupied` at the cells indexed by ``ix``, ``iy`` only (a few cells, without
        comparing the whole grid)."""
        return (self.evidence[ix, iy] > 0) | self.contact[ix, iy]

    def add_contact(self, xy) -> None:
        """The robot touched something at odom point ``xy``: its cell is an obstacle, kept
        (the hit point ``xy``) whatever scans say of it, until :meth:`clear`."""
        cell = self.cell_of(*xy)
        if cell is None:
            return
        self.contact[cell] = True
        self.hit_xy[cell] = xy

    def add_scan(self, origin_xy, ends_xy: np.ndarray, hits: np.ndarray,
                 clear_from_m: float = 0.0, stamp_s: float = 0.0, source: str = '') -> None:
        """Rays from ``origin_xy`` to ``ends_xy`` (N x 2, odom) taken at ``stamp_s`` by sensor
        ``source``: the floor along each ray from ``clear_from_m`` on is free, its end is an
        obstacle where ``hits`` is true (a ray without a return ends at the range it can vouch
        for). Nearer than ``clear_from_m`` the sensor is blind: what is remembered there stays,
        and the time since the same sensor's previous scan is added to the blind time and the
        blind-disc time of every cell within ``clear_from_m`` (at any bearing) and to the blind
        time of the cells along the rays there, except the obstacle cells along a ray whose hit
        lies within :data:`BLIND_EDGE_M` of ``clear_from_m``: the obstacle seen at the edge of
        the blind zone may reach into it, so their blind time starts again."""
        ends_xy = np.asarray(ends_xy, float).reshape(-1, 2)
        previous_s = self.scan_s.get(source)
        elapsed = 0.0 if previous_s is None else elapsed_s(stamp_s, previous_s)
        self.scan_s[source] = stamp_s
        disc_window = None
        if clear_from_m > 0.0 and elapsed > 0.0:
            ix, iy = self._window(origin_xy, clear_from_m)
            centres = self.centre_of(*np.meshgrid(ix, iy, indexing='ij'))
            disc = np.linalg.norm(centres - np.asarray(origin_xy, float), axis=-1) <= clear_from_m
            disc_window = np.ix_(ix, iy), disc
            self.blind_disc_s[disc_window[0]] += np.where(disc, elapsed, 0.0)
        if len(ends_xy) == 0:
            if disc_window is not None:
                self.blind_s[disc_window[0]] += np.where(disc_window[1], elapsed, 0.0)
            return
        origin = np.asarray(origin_xy, float).reshape(1, 2)
        step_m = self.resolution_m / 2.0
        lengths = np.linalg.norm(ends_xy - origin, axis=1)
        # free samples end one resolution short of a hit, so the hit's own cell stays occupied
        free_lengths = np.where(hits, lengths - self.resolution_m, lengths)
        samples = int(np.ceil(max(float(lengths.max()), step_m) / step_m)) + 1
        fractions = np.arange(samples) * step_m
        directions = (ends_xy - origin) / np.maximum(lengths, 1e-9)[:, None]
        points = origin[None, :, :] + fractions[None, :, None] * directions[:, None, :]
        along = fractions[None, :] <= free_lengths[:, None]
        beyond_blind = fractions[None, :] >= clear_from_m
        free = self._cells(points[along & beyond_blind])
        within_blind = (fractions[None, :] <= lengths[:, None]) & ~beyond_blind
        blind = self._cells(points[within_blind])
        at_edge = np.asarray(hits, bool) & (lengths <= clear_from_m + BLIND_EDGE_M)
        kept = (self._cells(points[within_blind & at_edge[:, None]]) & (self.evidence > 0)
                if at_edge.any() else None)
        if disc_window is not None:
            blind[disc_window[0]] |= disc_window[1]
        hits = np.asarray(hits, bool)
        # nearest to the sensor first: where one cell has several hits, that one is kept
        hit_xy = ends_xy[hits][np.argsort(lengths[hits], kind='stable')]
        hx, hy, hit_inside = self.index_of(hit_xy)
        hx, hy, hit_xy = hx[hit_inside], hy[hit_inside], hit_xy[hit_inside]
        _, first = np.unique(hx * self.cells + hy, return_index=True)
        hit = np.zeros_like(self.seen)
        hit[hx, hy] = True
        self.hit_xy[hx[first], hy[first]] = hit_xy[first]
        free &= ~hit
        blind &= ~hit
        self._observe_rays(origin, directions, lengths, hits, clear_from_m)
        self.evidence[free] = np.maximum(self.evidence[free] - MISS_EVIDENCE, -EVIDENCE_LIMIT)
        self.evidence[hit] = np.minimum(self.evidence[hit] + HIT_EVIDENCE, EVIDENCE_LIMIT)
        self.blind_s[hit] = 0.0
        self.blind_s[blind] += max(0.0, elapsed)
        if kept is not None:
            self.blind_s[kept] = 0.0

    def _observe_rays(self, origin: np.ndarray, directions: np.ndarray, lengths: np.ndarray,
                      hits: np.ndarray, clear_from_m: float) -> None:
        """Mark the fine cells along the rays from ``clear_from_m`` on as observed, up to one
        fine cell short of a hit, and the hit's own fine cell."""
        step_m = self.observed_resolution_m / 2.0
        free_lengths = np.where(hits, lengths - self.observed_resolution_m, lengths)
        fractions = np.arange(int(np.ceil(max(float(lengths.max()), step_m) / step_m)) + 1) \
            * step_m
        points = origin[None, :, :] + fractions[None, :, None] * directions[:, None, :]
        free = ((fractions[None, :] <= free_lengths[:, None])
                & (fractions[None, :] >= clear_from_m))
        ends = origin + lengths[hits][:, None] * directions[hits]
        fx, fy, inside = self._fine_index(np.concatenate((points[free], ends)))
        self.observed[fx[inside], fy[inside]] = True

    def _fine_index(self, xy: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(fx, fy, inside) of odom points on the observed layer's cells (clipped outside)."""
        ij = np.floor((np.asarray(xy, float).reshape(-1, 2) - self.origin_m)
                      / self.observed_resolution_m).astype(int)
        inside = np.all((ij >= 0) & (ij < len(self.observed)), axis=1)
        ij = np.clip(ij, 0, len(self.observed) - 1)
        return ij[:, 0], ij[:, 1], inside

    def _cells(self, xy: np.ndarray) -> np.ndarray:
        """Boolean grid of the cells holding any of the odom points ``xy`` (outside: none)."""
        ix, iy, inside = self.index_of(xy)
        cells = np.zeros_like(self.seen)
        cells[ix[inside], iy[inside]] = True
        return cells

    def mark_seen(self, camera_xy, heading_rad: float, half_fov_rad: float, near_m: float,
                  far_m: float) -> None:
        """Mark the floor wedge the camera covers: bearings within ``half_fov_rad`` of
        ``heading_rad``, from ``near_m`` to ``far_m`` from ``camera_xy`` (odom), each ray
        stopping at the first known obstacle."""
        if far_m <= near_m:
            return
        step_m = self.resolution_m / 2.0
        rays = int(math.ceil(2.0 * half_fov_rad * far_m / step_m)) + 1
        bearings = heading_rad + np.linspace(-half_fov_rad, half_fov_rad, rays)
        distances = np.arange(0.0, far_m + 1e-9, step_m)
        points = (np.asarray(camera_xy, float)[None, None, :]
                  + distances[None, :, None]
                  * np.stack((np.cos(bearings), np.sin(bearings)), axis=-1)[:, None, :])
        ix, iy, inside = self.index_of(points.reshape(-1, 2))
        blocked = (self.occupied()[ix, iy] | ~inside).reshape(rays, len(distances))
        visible = ~np.maximum.accumulate(blocked, axis=1)
        visible &= distances[None, :] >= near_m
        visible = visible.reshape(-1)
        self.seen[ix[visible], iy[visible]] = True

    def mark_observed(self, centre_xy, radius_m: float) -> None:
        """Count the fine cells whose centres lie within ``radius_m`` of odom point
        ``centre_xy`` as observed free floor (under the robot's body: it stands there)."""
        fx, fy = self._fine_window(centre_xy, radius_m)
        if len(fx) == 0 or len(fy) == 0:
            return
        centres = self._fine_centres(*np.meshgrid(fx, fy, indexing='ij'))
        near = np.linalg.norm(centres - np.asarray(centre_xy, float), axis=-1) <= radius_m
        self.observed[fx[0]:fx[-1] + 1, fy[0]:fy[-1] + 1] |= near

    def unknown_points(self, centre_xy, radius_m: float, max_blind_disc_s: float = np.inf,
                       max_blind_s: float = np.inf) -> np.ndarray:
        """Odom centres (N x 2) of the fine cells within ``radius_m`` of ``centre_xy`` that
        nothing has observed, outside remembered obstacle cells, and in cells that have been in
        a scan's blind disc for less than ``max_blind_disc_s`` (no ray can observe one from
        there, so it is taken for floor then) or that lie within :data:`OBSTACLE_REACH_M` of
        an obstacle cell scans have had in their blind zone for less than ``max_blind_s``
        (see :meth:`obstacle_points`): an obstacle seen from one side goes on into the unknown
        floor next to it, and a robot that waits beside it would otherwise take its unseen
        side for floor."""
        fx, fy = self._fine_window(centre_xy, radius_m)
        if len(fx) == 0 or len(fy) == 0:
            return np.zeros((0, 2))
        gx, gy = np.meshgrid(fx, fy, indexing='ij')
        cx, cy = gx // OBSERVED_SUBDIVISION, gy // OBSERVED_SUBDIVISION
        waiting = self.blind_disc_s[cx, cy] < max_blind_disc_s
        if not waiting.all():
            waiting |= self._near_obstacles(cx, cy, max_blind_s)
        unknown = ~self.observed[gx, gy] & ~self.occupied_at(cx, cy) & waiting
        points = self._fine_centres(gx[unknown], gy[unknown]).reshape(-1, 2)
        near = np.linalg.norm(points - np.asarray(centre_xy, float), axis=1) <= radius_m
        return points[near]

    def _near_obstacles(self, cx: np.ndarray, cy: np.ndarray, max_blind_s: float) -> np.ndarray:
        """Which of the coarse cells ``(cx, cy)`` (index arrays of one shape) lie within
        :data:`OBSTACLE_REACH_M` of an occupied cell that scans have had in their blind zone
        for less than ``max_blind_s``."""
        reach = int(math.ceil(OBSTACLE_REACH_M / self.resolution_m))
        x0, y0 = max(0, int(cx.min()) - reach), max(0, int(cy.min()) - reach)
        x1 = min(self.cells, int(cx.max()) + reach + 1)
        y1 = min(self.cells, int(cy.max()) + reach + 1)
        occupied = (self.occupied_at(slice(x0, x1), slice(y0, y1))
                    & (self.blind_s[x0:x1, y0:y1] < max_blind_s))
        near = inflate(occupied, OBSTACLE_REACH_M / self.resolution_m)
        return near[cx - x0, cy - y0]

    def _window(self, centre_xy, radius_m: float) -> Tuple[np.ndarray, np.ndarray]:
        """Index ranges (ix, iy) of the cells in the square around ``centre_xy`` holding the
        circle of ``radius_m`` (empty outside the grid)."""
        return self._index_window(centre_xy, radius_m, self.resolution_m, self.cells)

    def _fine_centres(self, fx, fy) -> np.ndarray:
        """Odom (x, y) of observed-layer cell centres (arrays broadcast)."""
        return np.stack((self.origin_m + (np.asarray(fx) + 0.5) * self.observed_resolution_m,
                         self.origin_m + (np.asarray(fy) + 0.5) * self.observed_resolution_m),
                        axis=-1)

    def _fine_window(self, centre_xy, radius_m: float) -> Tuple[np.ndarray, np.ndarray]:
        """Index ranges (fx, fy) of the observed layer's cells in the square around
        ``centre_xy`` holding the circle of ``radius_m`` (empty outside the grid)."""
        return self._index_window(centre_xy, radius_m, self.observed_resolution_m,
                                  len(self.observed))

    def _index_window(self, centre_xy, radius_m: float, resolution_m: float,
                      cells: int) -> Tuple[np.ndarray, np.ndarray]:
        """Index ranges of the square around ``centre_xy`` holding the circle of ``radius_m``
        on a layer of ``cells`` x ``cells`` cells of ``resolution_m``, clipped to it."""
        centre = np.asarray(centre_xy, float)
        low = np.floor((centre - radius_m - self.origin_m) / resolution_m).astype(int)
        high = np.floor((centre + radius_m - self.origin_m) / resolution_m).astype(int)
        low, high = np.maximum(low, 0), np.minimum(high, cells - 1)
        return np.arange(low[0], high[0] + 1), np.arange(low[1], high[1] + 1)

    def obstacle_points(self, centre_xy, radius_m: float,
                        max_blind_s: float = np.inf) -> np.ndarray:
        """Odom points (N x 2) of the occupied cells within ``radius_m`` of ``centre_xy`` that
        scans have had in their blind zone for less than ``max_blind_s`` since one last hit
        them (contacts whatever the time): where the last scan that hit each cell hit it, or
        the robot touched it (a cell's centre may lie half a cell behind the obstacle's
        surface)."""
        cells = int(math.ceil(radius_m / self.resolution_m)) + 1
        cx, cy, inside = self.index_of(np.asarray(centre_xy, float))
        if not inside[0]:
            return np.zeros((0, 2))
        x0, x1 = max(0, cx[0] - cells), min(self.cells, cx[0] + cells + 1)
        y0, y1 = max(0, cy[0] - cells), min(self.cells, cy[0] + cells + 1)
        ox, oy = np.nonzero(self.occupied_at(slice(x0, x1), slice(y0, y1))
                            & ((self.blind_s[x0:x1, y0:y1] < max_blind_s)
                               | self.contact[x0:x1, y0:y1]))
        points = self.hit_xy[ox + x0, oy + y0].reshape(-1, 2)
        near = np.linalg.norm(points - np.asarray(centre_xy, float), axis=1) <= radius_m
        return points[near]

    def _occupancy_data(self, known: np.ndarray) -> np.ndarray:
        """nav_msgs/OccupancyGrid data (rows along y, columns along x, row-major from the origin
        cell): 100 obstacle, 0 on the other ``known`` cells, -1 on the rest."""
        values = np.where(known, 0, -1).astype(np.int8)
        values[self.occupied()] = 100
        return values.T

    def coverage_values(self) -> np.ndarray:
        """The coverage as OccupancyGrid data: 100 obstacle, 0 floor the camera covered, -1 not
        covered."""
        return self._occupancy_data(self.seen)

    def obstacle_values(self) -> np.ndarray:
        """The obstacle memory as OccupancyGrid data: 100 obstacle, 0 where some ray or the
        robot's body has observed part of the cell, -1 unknown (nothing has seen that floor)."""
        fine = OBSERVED_SUBDIVISION
        return self._occupancy_data(
            self.observed.reshape(self.cells, fine, self.cells, fine).any(axis=(1, 3)))
