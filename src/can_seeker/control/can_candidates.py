"""Places where the can may stand, from an all-round range scan: small objects standing free.

A camera finds the can only where it looks, and a low camera pitched down sees the floor only
to well under a metre, so covering a room takes longer than a search may last. A lidar sees a
can across the room as a few returns: a short run of neighbouring returns, no wider than a can
and its beam spread, nearer than the returns on both sides of it (it stands in front of what
is behind it). Visiting such places first, camera pointed at them, finds the can sooner;
anything else that small (a thin post) costs one look.

Widths, gaps and ranges are compared on the micrometre (and bearings on the microradian)
lattice of :mod:`can_seeker.lattice`, so returns placed by sin and cos decide the same on every
CPU.
"""
import math
from typing import List

import numpy as np

from can_seeker.lattice import lattice

MAX_WIDTH_M = 0.12
"""Widest run of returns that may be a can (a can is 0.066 m across; beams add their spread)."""
JOIN_M = 0.05
"""Neighbouring returns nearer to each other than this belong to one object."""
STANDS_OUT_M = 0.15
"""The returns either side of a run must lie this much farther (or be none): it stands free."""
ALL_ROUND_RAD = math.pi
"""A scan spanning at least this many bearings sees all around (a lidar, not a camera scan)."""


def all_round(ends_xy: np.ndarray, origin_xy) -> bool:
    """True when the rays' bearings from ``origin_xy`` span at least :data:`ALL_ROUND_RAD`."""
    ends_xy = np.asarray(ends_xy, float).reshape(-1, 2)
    if len(ends_xy) < 2:
        return False
    offsets = ends_xy - np.asarray(origin_xy, float)
    bearings = np.sort(np.arctan2(offsets[:, 1], offsets[:, 0]))
    widest_gap = max(float(np.max(np.diff(bearings))),
                     2.0 * math.pi - float(bearings[-1] - bearings[0]))
    return bool(lattice(2.0 * math.pi - widest_gap) >= lattice(ALL_ROUND_RAD))


def small_objects(ends_xy: np.ndarray, hits: np.ndarray, origin_xy) -> List[np.ndarray]:
    """Centres (same frame as ``ends_xy``) of the runs of returns that may be a can: in ray
    order, joined while neighbours lie within :data:`JOIN_M`, at most :data:`MAX_WIDTH_M`
    wide, with the rays on both sides of the run reaching :data:`STANDS_OUT_M` farther or
    returning nothing. Each centre is pushed back from the sensor by a quarter of
    :data:`MAX_WIDTH_M`, about a can's radius (the returns come from its near face)."""
    ends_xy = np.asarray(ends_xy, float).reshape(-1, 2)
    hits = np.asarray(hits, bool).reshape(-1)
    origin = np.asarray(origin_xy, float)
    ends_um = lattice(ends_xy)
    offsets_um = ends_um - lattice(origin)
    ranges_um = np.rint(np.sqrt((offsets_um * offsets_um).sum(axis=1))).astype(np.int64)
    join_um, width_um, stands_out_um = (int(lattice(m))
                                        for m in (JOIN_M, MAX_WIDTH_M, STANDS_OUT_M))
    found = []
    count = len(ends_xy)
    start = 0
    while start < count:
        if not hits[start]:
            start += 1
            continue
        end = start
        while (end + 1 < count and hits[end + 1]
               and _squared(ends_um[end + 1] - ends_um[end]) < join_um * join_um):
            end += 1
        farthest_um = int(ranges_um[start:end + 1].max())
        sides = [index for index in (start - 1, end + 1) if 0 <= index < count]
        free = len(sides) == 2 and all(
            not hits[index] or ranges_um[index] > farthest_um + stands_out_um for index in sides)
        if _squared(ends_um[end] - ends_um[start]) <= width_um * width_um and free:
            centre = ends_xy[start:end + 1].mean(axis=0)
            away = (centre - origin) / max(float(np.linalg.norm(centre - origin)), 1e-9)
            found.append(centre + away * MAX_WIDTH_M / 4.0)
        start = end + 1
    return found


def _squared(offset_um: np.ndarray) -> int:
    """Squared length (um^2, exact) of an offset in whole micrometres."""
    return int((offset_um * offset_um).sum())
