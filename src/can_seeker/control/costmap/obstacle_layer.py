"""Obstacles from range scans and bumper contacts, remembered on the coarse grid (pure numpy).

A return adds four times what a ray passing through subtracts, both clamped; each obstacle
cell keeps where the nearest return of the last scan that hit it lay, and how long it has been
in a scan's blind zone since one last hit it (there no ray can clear a phantom). A contact is
an obstacle no scan clears. Design and reasons: docs/design/controller-and-safety.md.
"""
import numpy as np

from can_seeker.control.costmap.grid import GridGeometry, within
from can_seeker.control.costmap.scan_rays import ScanRays
from can_seeker.control.planner import inflate
from can_seeker.lattice import ceil_div, lattice

HIT_EVIDENCE = 4
MISS_EVIDENCE = 1
EVIDENCE_LIMIT = 12
BLIND_EDGE_M = 0.01
"""A return this near to a scan's range_min or nearer lies at the edge of its blind zone (see
:meth:`ObstacleLayer.update`)."""


class ObstacleLayer:
    """Obstacle evidence, hit points, contacts and blind-zone times of every coarse cell."""

    def __init__(self, grid: GridGeometry):
        self.grid = grid
        shape = (grid.cells, grid.cells)
        self.evidence = np.zeros(shape, np.int16)
        self.hit_xy = np.zeros(shape + (2,))
        self.contact = np.zeros(shape, bool)
        self.blind_s = np.zeros(shape)

    def clear(self) -> None:
        """Forget every obstacle and contact."""
        self.evidence[:] = 0
        self.blind_s[:] = 0.0
        self.contact[:] = False

    def occupied_at(self, ix, iy) -> np.ndarray:
        """Cells (indexed by ``ix``, ``iy``) with more evidence of an obstacle than of free
        floor, or a contact."""
        return (self.evidence[ix, iy] > 0) | self.contact[ix, iy]

    def add_contact(self, cell, xy) -> None:
        """The robot touched something at odom point ``xy`` in ``cell``: an obstacle there,
        kept (the hit point ``xy``) whatever scans say of it, until :meth:`clear`."""
        self.contact[cell] = True
        self.hit_xy[cell] = xy

    def update(self, rays: ScanRays) -> None:
        """The floor along each ray from the blind zone's edge on is free, its end an obstacle
        where it hit; the time since the sensor's previous scan is added to the blind time of
        every cell in its blind disc and along the rays there, except the obstacle cells along
        a ray whose hit lies within :data:`BLIND_EDGE_M` of the blind zone's edge: the
        obstacle seen there may reach into it, so their blind time starts again. A sample
        counts along the ray while it is no farther from the origin than the ray's end (one
        resolution nearer for a hit, so the hit's own cell stays occupied)."""
        elapsed, disc, grid = rays.elapsed_s, rays.disc, self.grid
        if rays.empty:
            if disc is not None:
                self.blind_s[disc[0]] += np.where(disc[1], elapsed, 0.0)
            return
        hits, fractions, cells = rays.hits, rays.coarse_fractions, rays.coarse_cells
        along = fractions[None, :] <= (rays.length_um - np.where(hits, grid.resolution_um,
                                                                 0))[:, None]
        beyond_blind = fractions[None, :] >= rays.clear_um
        free = rays.marked(cells[along & beyond_blind])
        within_blind = fractions[None, :] <= rays.length_um[:, None]
        within_blind &= ~beyond_blind
        blind = rays.marked(cells[within_blind])
        edge_um = rays.clear_um + int(lattice(BLIND_EDGE_M))
        at_edge = hits & (rays.squared <= edge_um * edge_um)
        kept = (rays.marked(cells[within_blind & at_edge[:, None]])
                & (self.evidence > 0) if at_edge.any() else None)
        if disc is not None:
            blind[disc[0]] |= disc[1]
        # nearest to the sensor first: where one cell has several hits, that one is kept
        nearest_first = np.argsort(rays.squared[hits], kind='stable')
        hit_xy = rays.ends_xy[hits][nearest_first]
        hx, hy, hit_inside = grid.lattice_index(rays.ends_um[hits][nearest_first],
                                                grid.resolution_um, grid.cells)
        hx, hy, hit_xy = hx[hit_inside], hy[hit_inside], hit_xy[hit_inside]
        _, first = np.unique(hx * grid.cells + hy, return_index=True)
        hit = np.zeros_like(self.contact)
        hit[hx, hy] = True
        self.hit_xy[hx[first], hy[first]] = hit_xy[first]
        free &= ~hit
        blind &= ~hit
        self.evidence[free] = np.maximum(self.evidence[free] - MISS_EVIDENCE, -EVIDENCE_LIMIT)
        self.evidence[hit] = np.minimum(self.evidence[hit] + HIT_EVIDENCE, EVIDENCE_LIMIT)
        self.blind_s[hit] = 0.0
        self.blind_s[blind] += max(0.0, elapsed)
        if kept is not None:
            self.blind_s[kept] = 0.0

    def points_near(self, centre_xy, radius_m: float, max_blind_s: float) -> np.ndarray:
        """Odom points (N x 2) of the occupied cells within ``radius_m`` of ``centre_xy`` that
        scans have had in their blind zone for less than ``max_blind_s`` since one last hit
        them (contacts whatever the time): where the last scan that hit each cell hit it, or
        the robot touched it (a cell's centre may lie half a cell behind the obstacle's
        surface)."""
        grid = self.grid
        centre, radius_um = lattice(centre_xy).reshape(2), int(lattice(radius_m))
        cells = int(ceil_div(radius_um, grid.resolution_um)) + 1
        cx, cy, inside = grid.lattice_index(centre.reshape(1, 2), grid.resolution_um, grid.cells)
        if not inside[0]:
            return np.zeros((0, 2))
        x0, x1 = max(0, cx[0] - cells), min(grid.cells, cx[0] + cells + 1)
        y0, y1 = max(0, cy[0] - cells), min(grid.cells, cy[0] + cells + 1)
        ox, oy = np.nonzero(self.occupied_at(slice(x0, x1), slice(y0, y1))
                            & ((self.blind_s[x0:x1, y0:y1] < max_blind_s)
                               | self.contact[x0:x1, y0:y1]))
        points = self.hit_xy[ox + x0, oy + y0].reshape(-1, 2)
        return points[within(lattice(points), centre, radius_um)]

    def near_recent(self, cx: np.ndarray, cy: np.ndarray, reach_m: float,
                    max_blind_s: float) -> np.ndarray:
        """Which of the coarse cells ``(cx, cy)`` (index arrays of one shape) lie within
        ``reach_m`` of an occupied cell that scans have had in their blind zone for less than
        ``max_blind_s``."""
        grid = self.grid
        reach_um = int(lattice(reach_m))
        reach = int(ceil_div(reach_um, grid.resolution_um))
        x0, y0 = max(0, int(cx.min()) - reach), max(0, int(cy.min()) - reach)
        x1 = min(grid.cells, int(cx.max()) + reach + 1)
        y1 = min(grid.cells, int(cy.max()) + reach + 1)
        occupied = (self.occupied_at(slice(x0, x1), slice(y0, y1))
                    & (self.blind_s[x0:x1, y0:y1] < max_blind_s))
        near = inflate(occupied, reach_um / grid.resolution_um)
        return near[cx - x0, cy - y0]
