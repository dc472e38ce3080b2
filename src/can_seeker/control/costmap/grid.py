"""The cells the map's layers share: a square grid centred on the odom origin, with cells of
half the size for the observed floor, on the micrometre lattice of :mod:`can_seeker.lattice`.

Arrays are indexed ``[ix, iy]``; cell (ix, iy) spans ``origin + (ix, iy) * resolution`` to one
resolution further. Odom positions outside the grid are ignored. Every discrete decision is
taken on positions snapped to whole micrometres, so the same input marks the same cells on
every CPU. Design and reasons: docs/design/controller-and-safety.md.
"""
import math
from typing import Optional, Tuple

import numpy as np

from can_seeker.lattice import SCALE, ceil_div, lattice

OBSERVED_SUBDIVISION = 2
"""Observed floor is kept on cells this many times finer than the obstacle grid's."""
RAY_STEPS_PER_CELL = 2
"""Rays are sampled this many times per cell side of the layer they mark (every half cell)."""


class GridGeometry:
    """Where each cell of a ``size_m`` square about the odom origin lies, coarse and fine."""

    def __init__(self, resolution_m: float, size_m: float):
        steps = OBSERVED_SUBDIVISION * RAY_STEPS_PER_CELL
        self.resolution_um = steps * max(1, int(round(float(resolution_m) * SCALE / steps)))
        self.fine_um = self.resolution_um // OBSERVED_SUBDIVISION
        self.resolution_m = self.resolution_um / SCALE
        self.cells = max(1, int(ceil_div(int(lattice(size_m)), self.resolution_um)))
        self.fine_cells = self.cells * OBSERVED_SUBDIVISION
        self.origin_um = -(self.cells * self.resolution_um // 2)
        self.origin_m = self.origin_um / SCALE
        self.observed_resolution_m = self.fine_um / SCALE

    def index_of(self, xy: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(ix, iy, inside) of odom points ``xy`` (N x 2); indices are clipped where outside."""
        return self.lattice_index(lattice(xy).reshape(-1, 2), self.resolution_um, self.cells)

    def lattice_index(self, xy_um: np.ndarray, resolution_um: int,
                      cells: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(i, j, inside) of points ``xy_um`` (N x 2, whole um, integers or integer-valued
        floats) on a layer of ``cells`` x ``cells`` cells of ``resolution_um`` from the origin;
        indices are clipped where outside. The floor of the rounded quotient of two integers
        below 2^52 is exactly the integer quotient."""
        ij = np.floor((xy_um - self.origin_um) / resolution_um).astype(np.int64)
        i, j = ij[:, 0], ij[:, 1]
        # negative indices wrap to huge unsigned ones: one comparison per bound
        inside = (i.view(np.uint64) < cells) & (j.view(np.uint64) < cells)
        np.maximum(ij, 0, out=ij)
        np.minimum(ij, cells - 1, out=ij)
        return i, j, inside

    def centres_um(self, i, j, resolution_um: int) -> np.ndarray:
        """(x, y) um of the centres of cells (i, j) on a layer of ``resolution_um``."""
        return np.stack((self.origin_um + np.asarray(i) * resolution_um + resolution_um // 2,
                         self.origin_um + np.asarray(j) * resolution_um + resolution_um // 2),
                        axis=-1)

    def cell_of(self, x_m: float, y_m: float) -> Optional[Tuple[int, int]]:
        """The cell holding odom point (x, y), or None outside the grid."""
        ix, iy, inside = self.index_of(np.array((x_m, y_m)))
        return (int(ix[0]), int(iy[0])) if inside[0] else None

    def centre_of(self, ix, iy) -> np.ndarray:
        """Odom (x, y) of cell centres (arrays broadcast)."""
        return self.centres_um(ix, iy, self.resolution_um) / SCALE

    def window(self, centre_um: np.ndarray, radius_um: int, resolution_um: int,
               cells: int) -> Tuple[np.ndarray, np.ndarray]:
        """Index ranges of the square around ``centre_um`` (x, y um) holding the circle of
        ``radius_um`` on a layer of ``cells`` x ``cells`` cells of ``resolution_um``, clipped
        to it (empty outside the grid)."""
        low = np.maximum((centre_um - radius_um - self.origin_um) // resolution_um, 0)
        high = np.minimum((centre_um + radius_um - self.origin_um) // resolution_um, cells - 1)
        return np.arange(low[0], high[0] + 1), np.arange(low[1], high[1] + 1)


def within(points_um: np.ndarray, centre_um: np.ndarray, radius_um: int) -> np.ndarray:
    """Which of ``points_um`` (..., 2, um) lie no farther than ``radius_um`` from
    ``centre_um`` (exact: squared integer distances)."""
    offsets = points_um - centre_um
    return (offsets * offsets).sum(axis=-1) <= radius_um * radius_um


def isqrt(squared: np.ndarray) -> np.ndarray:
    """Integer square roots (floor) of ``squared`` (int64, >= 0), exact: the float root is
    within one of it, and integer squares decide."""
    root = np.sqrt(squared.astype(float)).astype(np.int64)
    root -= root * root > squared
    root += (root + 1) * (root + 1) <= squared
    return root


def ray_samples(origin: np.ndarray, offsets: np.ndarray, squared: np.ndarray,
                step_um: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x N x M, y N x M, distances M) in whole um of the samples every ``step_um`` from
    ``origin`` (1 x 2 um) along the rays to ``origin + offsets`` (N x 2 um; ``squared`` their
    squared lengths), as many as the longest ray holds. Each point is the lattice point
    nearest to the exact one, as integer-valued floats: from integers by * / sqrt alone. The
    coordinates come as two arrays: each is one contiguous pass per operation."""
    distances = np.arange(math.isqrt(int(squared.max())) // step_um + 1, dtype=np.int64) * step_um
    along = distances.astype(float)[None, :]
    lengths = np.maximum(np.sqrt(squared.astype(float)), 1.0)[:, None]
    offsets = offsets.astype(float)
    coordinates = []
    for axis in range(2):
        values = along * offsets[:, axis:axis + 1]
        values /= lengths
        np.rint(values, out=values)
        values += origin[0, axis]
        coordinates.append(values)
    return coordinates[0], coordinates[1], distances
