"""Discrete decisions that a last-bit difference cannot change: values on a lattice of millionths.

Basic IEEE arithmetic (+ - * / sqrt) rounds the same on every CPU, but transcendental functions
(sin, cos, arctan2, ...) may differ in the last bit from one SIMD kernel to another. A point
meant to lie at 0.45 m then comes out a hair either side of it, and a cell boundary there
decides by that hair. Snapped to millionths (micrometres for lengths, microradians for angles,
millionths of a cell or bin for ratios), every such value lands exactly on its lattice point:
the decision's knife edge moves to half a millionth away, where nice inputs never lie.
"""
import numpy as np

SCALE = 1_000_000
"""Lattice points per unit (m, rad, cell)."""


def lattice(values) -> np.ndarray:
    """``values`` in whole millionths (int64; µm for metres, µrad for radians)."""
    return np.rint(np.asarray(values, float) * SCALE).astype(np.int64)


def snapped(values) -> np.ndarray:
    """``values`` (float, NaN stays NaN) moved to the nearest millionth: a value a last bit off
    an integer becomes that integer exactly."""
    return np.rint(np.asarray(values, float) * SCALE) / SCALE


def floor(values) -> np.ndarray:
    """``np.floor`` of :func:`snapped` ``values`` (float, NaN stays NaN)."""
    return np.floor(snapped(values))


def ceil(values) -> np.ndarray:
    """``np.ceil`` of :func:`snapped` ``values`` (float, NaN stays NaN)."""
    return np.ceil(snapped(values))


def ceil_div(numerator, denominator):
    """Smallest integer not below ``numerator / denominator`` (integers, denominator > 0)."""
    return -(-numerator // denominator)
