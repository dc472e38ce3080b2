"""What the robot has learnt about the floor, on a coarse grid in the odom frame.

Layers over the same square cells: obstacle evidence from range scans (a hit adds four times
what a ray passing through subtracts, both clamped), with how long each obstacle cell has been
in a scan's blind zone since one last hit it; contacts where a bumper touched something (never
cleared by scans, only by :meth:`GridMap.clear`); coverage, the floor the camera has looked at;
and, on cells of half the size, the floor some ray, the robot's body or its start observed, the
rest being unknown floor the safety layer keeps off. Each coarse cell also counts how long it
has been within a scan's blind disc, from where no turn can observe it.

Arrays are indexed ``[ix, iy]``; cell (ix, iy) spans ``origin + (ix, iy) * resolution`` to one
resolution further. Odom positions outside the grid are ignored. Every discrete decision is
taken on positions snapped to whole micrometres (:mod:`can_seeker.lattice`), so the same scan
marks the same cells on every CPU. Design and reasons: docs/design/controller-and-safety.md.
"""
import math
from typing import Dict, Optional, Tuple

import numpy as np

from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.planner import inflate
from can_seeker.lattice import SCALE, ceil_div, lattice

HIT_EVIDENCE = 4
MISS_EVIDENCE = 1
EVIDENCE_LIMIT = 12
OBSERVED_SUBDIVISION = 2
"""Observed floor is kept on cells this many times finer than the obstacle grid's."""
BLIND_EDGE_M = 0.01
"""A return this near to a scan's range_min or nearer lies at the edge of its blind zone (see
:meth:`GridMap.add_scan`)."""
RAY_STEPS_PER_CELL = 2
"""Rays are sampled this many times per cell side of the layer they mark (every half cell)."""
OBSTACLE_REACH_M = 0.3
"""Unknown floor this near a remembered obstacle cell is never taken for floor by waiting: a
camera that saw one side of an obstacle has not seen how far it goes on (a box's unseen
corner, a round table's far rim)."""


class GridMap:
    """Obstacle evidence and camera coverage of a ``size_m`` square centred on the odom origin."""

    def __init__(self, resolution_m: float, size_m: float):
        steps = OBSERVED_SUBDIVISION * RAY_STEPS_PER_CELL
        self._resolution_um = steps * max(1, int(round(float(resolution_m) * SCALE / steps)))
        self._fine_um = self._resolution_um // OBSERVED_SUBDIVISION
        self.resolution_m = self._resolution_um / SCALE
        self.cells = max(1, int(ceil_div(int(lattice(size_m)), self._resolution_um)))
        self._origin_um = -(self.cells * self._resolution_um // 2)
        self.origin_m = self._origin_um / SCALE
        self.evidence = np.zeros((self.cells, self.cells), np.int16)
        self.seen = np.zeros((self.cells, self.cells), bool)
        self.observed_resolution_m = self._fine_um / SCALE
        self.observed = np.zeros((self.cells * OBSERVED_SUBDIVISION,) * 2, bool)
        self.blind_s = np.zeros((self.cells, self.cells))
        self.blind_disc_s = np.zeros((self.cells, self.cells))
        self.scan_s: Dict[str, float] = {}
        self.hit_xy = np.zeros((self.cells, self.cells, 2))
        self.contact = np.zeros((self.cells, self.cells), bool)
        self.changes = 0
        """Counts the calls that changed the obstacle and observed layers (scans, contacts,
        the robot's body, clearing): answers derived from them stay valid while it stands."""

    def clear(self) -> None:
        """Forget every obstacle and all coverage."""
        self.changes += 1
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
        return self._lattice_index(lattice(xy).reshape(-1, 2), self._resolution_um, self.cells)

    def _lattice_index(self, xy_um: np.ndarray, resolution_um: int,
                       cells: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(i, j, inside) of points ``xy_um`` (N x 2, whole um, integers or integer-valued
        floats) on a layer of ``cells`` x ``cells`` cells of ``resolution_um`` from the origin;
        indices are clipped where outside. The floor of the rounded quotient of two integers
        below 2^52 is exactly the integer quotient."""
        ij = np.floor((xy_um - self._origin_um) / resolution_um).astype(np.int64)
        inside = np.all((ij >= 0) & (ij < cells), axis=1)
        ij = np.clip(ij, 0, cells - 1)
        return ij[:, 0], ij[:, 1], inside

    def _centres_um(self, i, j, resolution_um: int) -> np.ndarray:
        """(x, y) um of the centres of cells (i, j) on a layer of ``resolution_um``."""
        return np.stack((self._origin_um + np.asarray(i) * resolution_um + resolution_um // 2,
                         self._origin_um + np.asarray(j) * resolution_um + resolution_um // 2),
                        axis=-1)

    def cell_of(self, x_m: float, y_m: float) -> Optional[Tuple[int, int]]:
        """The cell holding odom point (x, y), or None outside the grid."""
        ix, iy, inside = self.index_of(np.array((x_m, y_m)))
        return (int(ix[0]), int(iy[0])) if inside[0] else None

    def centre_of(self, ix, iy) -> np.ndarray:
        """Odom (x, y) of cell centres (arrays broadcast)."""
        return self._centres_um(ix, iy, self._resolution_um) / SCALE

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
        self.changes += 1
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
        the blind zone may reach into it, so their blind time starts again. Each ray is sampled
        every half resolution from its origin; a sample counts along the ray while it is no
        farther from the origin than the ray's end (one resolution nearer for a hit, so the
        hit's own cell stays occupied)."""
        self.changes += 1
        ends_xy = np.asarray(ends_xy, float).reshape(-1, 2)
        previous_s = self.scan_s.get(source)
        elapsed = 0.0 if previous_s is None else elapsed_s(stamp_s, previous_s)
        self.scan_s[source] = stamp_s
        origin = lattice(origin_xy).reshape(1, 2)
        clear_um = int(lattice(clear_from_m))
        disc_window = None
        if clear_um > 0 and elapsed > 0.0:
            ix, iy = self._window(origin[0], clear_um, self._resolution_um, self.cells)
            centres = self._centres_um(*np.meshgrid(ix, iy, indexing='ij'), self._resolution_um)
            disc = _within(centres, origin[0], clear_um)
            disc_window = np.ix_(ix, iy), disc
            self.blind_disc_s[disc_window[0]] += np.where(disc, elapsed, 0.0)
        if len(ends_xy) == 0:
            if disc_window is not None:
                self.blind_s[disc_window[0]] += np.where(disc_window[1], elapsed, 0.0)
            return
        hits = np.asarray(hits, bool).reshape(-1)
        ends = lattice(ends_xy)
        offsets = ends - origin
        squared = (offsets * offsets).sum(axis=1)
        # One sampling serves both layers: every OBSERVED_SUBDIVISION-th fine sample is a coarse
        # one (the same lattice point), as a coarse cell is that many fine cells a side.
        points, fractions = _ray_samples(origin, offsets, squared,
                                         self._fine_um // RAY_STEPS_PER_CELL)
        fine_cells, coarse_cells = self._sample_cells(points)
        coarse_fractions = fractions[::OBSERVED_SUBDIVISION]
        # A sample at f lies no farther than r from the origin where f <= isqrt(r^2).
        length_um = _isqrt(squared)
        along = coarse_fractions[None, :] <= (length_um - np.where(hits, self._resolution_um,
                                                                   0))[:, None]
        beyond_blind = coarse_fractions[None, :] >= clear_um
        free = self._marked(coarse_cells[along & beyond_blind])
        within_blind = coarse_fractions[None, :] <= length_um[:, None]
        within_blind &= ~beyond_blind
        blind = self._marked(coarse_cells[within_blind])
        edge_um = clear_um + int(lattice(BLIND_EDGE_M))
        at_edge = hits & (squared <= edge_um * edge_um)
        kept = (self._marked(coarse_cells[within_blind & at_edge[:, None]])
                & (self.evidence > 0) if at_edge.any() else None)
        if disc_window is not None:
            blind[disc_window[0]] |= disc_window[1]
        # nearest to the sensor first: where one cell has several hits, that one is kept
        nearest_first = np.argsort(squared[hits], kind='stable')
        hit_xy = ends_xy[hits][nearest_first]
        hx, hy, hit_inside = self._lattice_index(ends[hits][nearest_first], self._resolution_um,
                                                 self.cells)
        hx, hy, hit_xy = hx[hit_inside], hy[hit_inside], hit_xy[hit_inside]
        _, first = np.unique(hx * self.cells + hy, return_index=True)
        hit = np.zeros_like(self.seen)
        hit[hx, hy] = True
        self.hit_xy[hx[first], hy[first]] = hit_xy[first]
        free &= ~hit
        blind &= ~hit
        fine_free = ((fractions[None, :] <= (length_um - np.where(hits, self._fine_um, 0))[:, None])
                     & (fractions[None, :] >= clear_um))
        hx, hy, hit_inside = self._lattice_index(ends[hits], self._fine_um, len(self.observed))
        observed = self.observed.reshape(-1)
        seen_free = fine_cells[fine_free]
        observed[seen_free[seen_free >= 0]] = True
        observed[hx[hit_inside] * len(self.observed) + hy[hit_inside]] = True
        self.evidence[free] = np.maximum(self.evidence[free] - MISS_EVIDENCE, -EVIDENCE_LIMIT)
        self.evidence[hit] = np.minimum(self.evidence[hit] + HIT_EVIDENCE, EVIDENCE_LIMIT)
        self.blind_s[hit] = 0.0
        self.blind_s[blind] += max(0.0, elapsed)
        if kept is not None:
            self.blind_s[kept] = 0.0

    def _sample_cells(self, points_um: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(fine, coarse) flat indices of the cells holding the fine samples ``points_um``
        (N x M x 2, whole um; overwritten) and of every :data:`OBSERVED_SUBDIVISION`-th of
        them (the coarse samples), -1 outside the grid (see :meth:`_lattice_index`; a fine
        cell's indices divided by the subdivision are its coarse cell's)."""
        fine_cells = len(self.observed)
        np.subtract(points_um, self._origin_um, out=points_um)
        np.divide(points_um, self._fine_um, out=points_um)
        np.floor(points_um, out=points_um)
        fx, fy = points_um[..., 0].astype(np.int64), points_um[..., 1].astype(np.int64)
        # negative indices wrap to huge unsigned ones: one comparison per bound
        inside = ((fx.view(np.uint64) < fine_cells) & (fy.view(np.uint64) < fine_cells))
        fine = np.where(inside, fx * fine_cells + fy, -1)
        step = OBSERVED_SUBDIVISION
        coarse = np.where(inside[:, ::step], (fx[:, ::step] // step) * self.cells
                          + fy[:, ::step] // step, -1)
        return fine, coarse

    def _marked(self, flat_cells: np.ndarray) -> np.ndarray:
        """Boolean coarse layer of the cells ``flat_cells`` (flat indices, -1: outside, none)."""
        marked = np.zeros(self.cells * self.cells + 1, bool)
        marked[flat_cells] = True
        return marked[:-1].reshape(self.cells, self.cells)

    def mark_seen(self, camera_xy, heading_rad: float, half_fov_rad: float, near_m: float,
                  far_m: float) -> None:
        """Mark the floor wedge the camera covers: bearings within ``half_fov_rad`` of
        ``heading_rad``, from ``near_m`` to ``far_m`` from ``camera_xy`` (odom), each ray
        stopping at the first known obstacle."""
        near_um, far_um = int(lattice(near_m)), int(lattice(far_m))
        if far_um <= near_um:
            return
        step_um = self._resolution_um // RAY_STEPS_PER_CELL
        rays = int(ceil_div(int(lattice(2.0 * half_fov_rad * far_m)), step_um)) + 1
        bearings = heading_rad + np.linspace(-half_fov_rad, half_fov_rad, rays)
        distances_um = np.arange(far_um // step_um + 1) * step_um
        points = (np.asarray(camera_xy, float)[None, None, :]
                  + (distances_um / SCALE)[None, :, None]
                  * np.stack((np.cos(bearings), np.sin(bearings)), axis=-1)[:, None, :])
        ix, iy, inside = self.index_of(points.reshape(-1, 2))
        blocked = (self.occupied_at(ix, iy) | ~inside).reshape(rays, len(distances_um))
        visible = ~np.maximum.accumulate(blocked, axis=1)
        visible &= distances_um[None, :] >= near_um
        visible = visible.reshape(-1)
        self.seen[ix[visible], iy[visible]] = True

    def mark_observed(self, centre_xy, radius_m: float) -> None:
        """Count the fine cells whose centres lie within ``radius_m`` of odom point
        ``centre_xy`` as observed free floor (under the robot's body: it stands there)."""
        centre, radius_um = lattice(centre_xy).reshape(2), int(lattice(radius_m))
        fx, fy = self._window(centre, radius_um, self._fine_um, len(self.observed))
        if len(fx) == 0 or len(fy) == 0:
            return
        self.changes += 1
        # the disc's squared distances as a sum of a column and a row (exact integers)
        dx = self._origin_um + fx * self._fine_um + self._fine_um // 2 - centre[0]
        dy = self._origin_um + fy * self._fine_um + self._fine_um // 2 - centre[1]
        self.observed[fx[0]:fx[-1] + 1, fy[0]:fy[-1] + 1] |= (
            (dx * dx)[:, None] + (dy * dy)[None, :] <= radius_um * radius_um)

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
        centre, radius_um = lattice(centre_xy).reshape(2), int(lattice(radius_m))
        fx, fy = self._window(centre, radius_um, self._fine_um, len(self.observed))
        if len(fx) == 0 or len(fy) == 0:
            return np.zeros((0, 2))
        gx, gy = np.meshgrid(fx, fy, indexing='ij')
        cx, cy = gx // OBSERVED_SUBDIVISION, gy // OBSERVED_SUBDIVISION
        waiting = self.blind_disc_s[cx, cy] < max_blind_disc_s
        if not waiting.all():
            waiting |= self._near_obstacles(cx, cy, max_blind_s)
        unknown = ~self.observed[gx, gy] & ~self.occupied_at(cx, cy) & waiting
        points = self._centres_um(gx[unknown], gy[unknown], self._fine_um).reshape(-1, 2)
        return points[_within(points, centre, radius_um)] / SCALE

    def _near_obstacles(self, cx: np.ndarray, cy: np.ndarray, max_blind_s: float) -> np.ndarray:
        """Which of the coarse cells ``(cx, cy)`` (index arrays of one shape) lie within
        :data:`OBSTACLE_REACH_M` of an occupied cell that scans have had in their blind zone
        for less than ``max_blind_s``."""
        reach_um = int(lattice(OBSTACLE_REACH_M))
        reach = int(ceil_div(reach_um, self._resolution_um))
        x0, y0 = max(0, int(cx.min()) - reach), max(0, int(cy.min()) - reach)
        x1 = min(self.cells, int(cx.max()) + reach + 1)
        y1 = min(self.cells, int(cy.max()) + reach + 1)
        occupied = (self.occupied_at(slice(x0, x1), slice(y0, y1))
                    & (self.blind_s[x0:x1, y0:y1] < max_blind_s))
        near = inflate(occupied, reach_um / self._resolution_um)
        return near[cx - x0, cy - y0]

    def _window(self, centre_um: np.ndarray, radius_um: int, resolution_um: int,
                cells: int) -> Tuple[np.ndarray, np.ndarray]:
        """Index ranges of the square around ``centre_um`` (x, y um) holding the circle of
        ``radius_um`` on a layer of ``cells`` x ``cells`` cells of ``resolution_um``, clipped
        to it (empty outside the grid)."""
        low = np.maximum((centre_um - radius_um - self._origin_um) // resolution_um, 0)
        high = np.minimum((centre_um + radius_um - self._origin_um) // resolution_um, cells - 1)
        return np.arange(low[0], high[0] + 1), np.arange(low[1], high[1] + 1)

    def obstacle_points(self, centre_xy, radius_m: float,
                        max_blind_s: float = np.inf) -> np.ndarray:
        """Odom points (N x 2) of the occupied cells within ``radius_m`` of ``centre_xy`` that
        scans have had in their blind zone for less than ``max_blind_s`` since one last hit
        them (contacts whatever the time): where the last scan that hit each cell hit it, or
        the robot touched it (a cell's centre may lie half a cell behind the obstacle's
        surface)."""
        centre, radius_um = lattice(centre_xy).reshape(2), int(lattice(radius_m))
        cells = int(ceil_div(radius_um, self._resolution_um)) + 1
        cx, cy, inside = self._lattice_index(centre.reshape(1, 2), self._resolution_um,
                                             self.cells)
        if not inside[0]:
            return np.zeros((0, 2))
        x0, x1 = max(0, cx[0] - cells), min(self.cells, cx[0] + cells + 1)
        y0, y1 = max(0, cy[0] - cells), min(self.cells, cy[0] + cells + 1)
        ox, oy = np.nonzero(self.occupied_at(slice(x0, x1), slice(y0, y1))
                            & ((self.blind_s[x0:x1, y0:y1] < max_blind_s)
                               | self.contact[x0:x1, y0:y1]))
        points = self.hit_xy[ox + x0, oy + y0].reshape(-1, 2)
        return points[_within(lattice(points), centre, radius_um)]

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


def _within(points_um: np.ndarray, centre_um: np.ndarray, radius_um: int) -> np.ndarray:
    """Which of ``points_um`` (..., 2, um) lie no farther than ``radius_um`` from
    ``centre_um`` (exact: squared integer distances)."""
    offsets = points_um - centre_um
    return (offsets * offsets).sum(axis=-1) <= radius_um * radius_um


def _isqrt(squared: np.ndarray) -> np.ndarray:
    """Integer square roots (floor) of ``squared`` (int64, >= 0), exact: the float root is
    within one of it, and integer squares decide."""
    root = np.sqrt(squared.astype(float)).astype(np.int64)
    root -= root * root > squared
    root += (root + 1) * (root + 1) <= squared
    return root


def _ray_samples(origin: np.ndarray, offsets: np.ndarray, squared: np.ndarray,
                 step_um: int) -> Tuple[np.ndarray, np.ndarray]:
    """(points N x M x 2, distances M) in whole um of the samples every ``step_um`` from
    ``origin`` (1 x 2 um) along the rays to ``origin + offsets`` (N x 2 um; ``squared`` their
    squared lengths), as many as the longest ray holds. Each point is the lattice point
    nearest to the exact one, as integer-valued floats: from integers by * / sqrt alone."""
    distances = np.arange(math.isqrt(int(squared.max())) // step_um + 1, dtype=np.int64) * step_um
    lengths = np.maximum(np.sqrt(squared.astype(float)), 1.0)
    points = distances.astype(float)[None, :, None] * offsets.astype(float)[:, None, :]
    points /= lengths[:, None, None]
    np.rint(points, out=points)
    points += origin[None, :, :]
    return points, distances
