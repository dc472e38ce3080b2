"""One range scan as the map's layers read it: its rays sampled once on the grid, and the
blind disc about its sensor (pure numpy, no ROS)."""
from typing import Optional, Tuple

import numpy as np

from can_seeker.control.costmap.grid import (OBSERVED_SUBDIVISION, RAY_STEPS_PER_CELL,
                                             GridGeometry, isqrt, ray_samples, within)
from can_seeker.lattice import lattice


class ScanRays:
    """Rays from ``origin_xy`` to ``ends_xy`` (N x 2, odom; ``hits``: a return at the end)
    with the sensor blind nearer than ``clear_from_m``, ``elapsed_s`` after the same sensor's
    previous scan. Each ray is sampled every half fine cell from its origin; every
    :data:`OBSERVED_SUBDIVISION`-th fine sample is a coarse one (the same lattice point), so
    one sampling serves the coarse layers and the fine one."""

    def __init__(self, grid: GridGeometry, origin_xy, ends_xy: np.ndarray, hits: np.ndarray,
                 clear_from_m: float, elapsed_s: float):
        self.grid = grid
        self.elapsed_s = elapsed_s
        self.ends_xy = np.asarray(ends_xy, float).reshape(-1, 2)
        self.origin_um = lattice(origin_xy).reshape(1, 2)
        self.clear_um = int(lattice(clear_from_m))
        self.disc: Optional[Tuple[Tuple, np.ndarray]] = None
        """(index window, mask) of the coarse cells within ``clear_from_m`` of the sensor (at
        any bearing), when it is blind there and time has passed since its last scan."""
        if self.clear_um > 0 and elapsed_s > 0.0:
            ix, iy = grid.window(self.origin_um[0], self.clear_um, grid.resolution_um, grid.cells)
            centres = grid.centres_um(*np.meshgrid(ix, iy, indexing='ij'), grid.resolution_um)
            self.disc = np.ix_(ix, iy), within(centres, self.origin_um[0], self.clear_um)
        if len(self.ends_xy) == 0:
            return
        self.hits = np.asarray(hits, bool).reshape(-1)
        self.ends_um = lattice(self.ends_xy)
        offsets = self.ends_um - self.origin_um
        self.squared = (offsets * offsets).sum(axis=1)
        # sampled from the grid's corner: integers below 2^53 add exactly in any order
        x_um, y_um, self.fractions = ray_samples(self.origin_um - grid.origin_um, offsets,
                                                 self.squared, grid.fine_um // RAY_STEPS_PER_CELL)
        self.fine_cells, self.coarse_cells = self._sample_cells(x_um, y_um)
        self.coarse_fractions = self.fractions[::OBSERVED_SUBDIVISION]
        # A sample at f lies no farther than r from the origin where f <= isqrt(r^2).
        self.length_um = isqrt(self.squared)

    @property
    def empty(self) -> bool:
        """True for a scan without rays."""
        return len(self.ends_xy) == 0

    def _sample_cells(self, x_um: np.ndarray, y_um: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(fine, coarse) flat indices of the cells holding the fine samples at ``x_um``,
        ``y_um`` (N x M each, whole um from the grid's corner; overwritten) and of every
        :data:`OBSERVED_SUBDIVISION`-th of them (the coarse samples), -1 outside the grid (see
        :meth:`GridGeometry.lattice_index`; a fine cell's indices divided by the subdivision
        are its coarse cell's)."""
        fine_cells, grid = self.grid.fine_cells, self.grid
        fine = []
        for values in (x_um, y_um):
            np.divide(values, grid.fine_um, out=values)
            # the floor written straight as integers: one pass, no float copy to convert
            index = np.empty(values.shape, np.int64)
            np.floor(values, out=index, casting='unsafe')
            fine.append(index)
        fx, fy = fine
        # negative indices wrap to huge unsigned ones: one comparison per bound
        outside = fx.view(np.uint64) >= fine_cells
        outside |= fy.view(np.uint64) >= fine_cells
        step = OBSERVED_SUBDIVISION
        # the coarse samples' indices written contiguously by the division itself
        coarse = np.floor_divide(fx[:, ::step], step)
        coarse *= grid.cells
        coarse += np.floor_divide(fy[:, ::step], step)
        fx *= fine_cells
        fx += fy
        fx[outside] = -1
        coarse[outside[:, ::step]] = -1
        return fx, coarse

    def marked(self, flat_cells: np.ndarray) -> np.ndarray:
        """Boolean coarse layer of the cells ``flat_cells`` (flat indices, -1: outside, none)."""
        cells = self.grid.cells
        marked = np.zeros(cells * cells + 1, bool)
        marked[flat_cells] = True
        return marked[:-1].reshape(cells, cells)
