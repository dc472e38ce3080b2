"""Paths on the obstacle grid and exploration goals (pure numpy, no ROS).

Obstacles are grown by the robot's radius plus a margin (``inflate``), so the robot's centre
may go anywhere that is not blocked. Distances from the robot's cell come from a vectorised
wavefront (8-connected, diagonal steps cost sqrt(2)) over the known part of the grid plus a
margin; unknown floor counts as free (it is checked again as soon as the camera sees it).
A path is read back by steepest descent of those distances.
"""
import math
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from can_seeker.lattice import lattice

NEIGHBOURS = ((1, 0, 1.0), (-1, 0, 1.0), (0, 1, 1.0), (0, -1, 1.0),
              (1, 1, math.sqrt(2.0)), (1, -1, math.sqrt(2.0)),
              (-1, 1, math.sqrt(2.0)), (-1, -1, math.sqrt(2.0)))


def shifted(array: np.ndarray, dx: int, dy: int, fill) -> np.ndarray:
    """``array`` moved by (dx, dy) cells: result[i, j] = array[i - dx, j - dy], ``fill`` outside."""
    result = np.full_like(array, fill)
    nx, ny = array.shape
    result[max(0, dx):nx + min(0, dx), max(0, dy):ny + min(0, dy)] = \
        array[max(0, -dx):nx - max(0, dx), max(0, -dy):ny - max(0, dy)]
    return result


def inflate(blocked: np.ndarray, radius_cells: float) -> np.ndarray:
    """Cells within ``radius_cells`` (centre to centre) of a blocked cell: the disc as rows of
    offsets, each row the blocked cells grown along y by its half width, moved along x."""
    reach = int(math.floor(radius_cells))
    half_widths = [max([dy for dy in range(reach + 1) if dx * dx + dy * dy
                        <= radius_cells * radius_cells], default=-1)
                   for dx in range(-reach, reach + 1)]
    along_y = [blocked]
    for half_width in range(1, max(half_widths) + 1):
        along_y.append(along_y[-1] | shifted(blocked, 0, half_width, False)
                       | shifted(blocked, 0, -half_width, False))
    grown = blocked.copy()
    for dx, half_width in zip(range(-reach, reach + 1), half_widths):
        if half_width >= 0:
            grown |= shifted(along_y[half_width], dx, 0, False)
    return grown


def wavefront(free: np.ndarray, start: Tuple[int, int]) -> np.ndarray:
    """Path length in cells from ``start`` to every cell through ``free`` cells (inf where
    unreachable). The start counts as free.

    Each cell's length is the least, over the paths to it, of the steps' costs added one by
    one from the start: relaxed in place (each neighbour's step in turn) over only the rows
    next to those the last sweep shortened, until a sweep shortens none. Every order of such
    relaxations ends at those least sums (a float sum only grows with each step), so this
    gives the lengths of whole-grid sweeps to the last bit."""
    nx, ny = free.shape
    width = ny + 2
    # Row-major with a border of blocked cells all round and one more cell at either end: a
    # neighbour is a fixed offset away, and the rows a sweep covers are one contiguous run.
    passable = np.zeros((nx + 2, width), bool)
    passable[1:-1, 1:-1] = free
    passable[start[0] + 1, start[1] + 1] = True
    passable = np.concatenate(([False], passable.reshape(-1), [False]))
    distance = np.full(len(passable), np.inf)
    distance[1 + (start[0] + 1) * width + start[1] + 1] = 0.0
    # a step's cost into each cell: inf into a blocked one (x + 0.0 is x to the last bit)
    step_costs = {cost: np.where(passable, cost, np.inf) for cost in {1.0, math.sqrt(2.0)}}
    offsets = [(dx * width + dy, cost) for dx, dy, cost in NEIGHBOURS]
    low, high = start[0] + 1, start[0] + 2
    while True:
        low, high = max(low - 1, 1), min(high + 1, nx + 1)
        begin, end = 1 + low * width, 1 + high * width
        region = distance[begin:end]
        before = region.copy()
        reached = np.empty_like(region)
        for offset, cost in offsets:
            np.add(distance[begin - offset:end - offset], step_costs[cost][begin:end],
                   out=reached)
            np.minimum(region, reached, out=region)
        changed = np.flatnonzero(region != before)
        if len(changed) == 0:
            return distance[1:-1].reshape(nx + 2, width)[1:-1, 1:-1].copy()
        low, high = low + int(changed[0]) // width, low + int(changed[-1]) // width + 1


def descend(distance: np.ndarray, goal: Tuple[int, int]) -> List[Tuple[int, int]]:
    """Cells from the start (distance 0) to ``goal`` along steepest descent of ``distance``."""
    path = [goal]
    cell = goal
    while distance[cell] > 0.0:
        candidates = [(cell[0] + dx, cell[1] + dy) for dx, dy, _ in NEIGHBOURS
                      if 0 <= cell[0] + dx < distance.shape[0]
                      and 0 <= cell[1] + dy < distance.shape[1]]
        nxt = min(candidates, key=lambda c: distance[c])
        if distance[nxt] >= distance[cell]:
            break
        path.append(nxt)
        cell = nxt
    path.reverse()
    return path


@dataclass(frozen=True)
class Window:
    """A rectangle of grid cells ``[x0, x1) x [y0, y1)`` where planning happens."""

    x0: int
    x1: int
    y0: int
    y1: int

    def crop(self, array: np.ndarray) -> np.ndarray:
        return array[self.x0:self.x1, self.y0:self.y1]

    def local(self, cell: Tuple[int, int]) -> Tuple[int, int]:
        return cell[0] - self.x0, cell[1] - self.y0

    def grid(self, cell: Tuple[int, int]) -> Tuple[int, int]:
        return cell[0] + self.x0, cell[1] + self.y0


def planning_window(known: np.ndarray, cells: Tuple[Tuple[int, int], ...],
                    margin_cells: int) -> Window:
    """The bounding box of the ``known`` cells and the given ``cells``, grown by a margin and
    clipped to the grid: beyond it nothing is known, so nothing there is worth planning."""
    xs, ys = np.nonzero(known)
    xs = np.concatenate((xs, [c[0] for c in cells])).astype(int)
    ys = np.concatenate((ys, [c[1] for c in cells])).astype(int)
    return Window(max(0, int(xs.min()) - margin_cells),
                  min(known.shape[0], int(xs.max()) + margin_cells + 1),
                  max(0, int(ys.min()) - margin_cells),
                  min(known.shape[1], int(ys.max()) + margin_cells + 1))


def frontier_goal(distance: np.ndarray, seen: np.ndarray, blocked: np.ndarray,
                  robot_cell: Tuple[int, int], heading_rad: float, resolution_m: float,
                  turn_cost_m_per_rad: float, min_unseen_cells: int,
                  min_distance_cells: float = 0.0, previous: Optional[Tuple[int, int]] = None,
                  switch_m: float = 0.0) -> Optional[Tuple[int, int]]:
    """The reachable, unseen, unblocked cell next to seen floor with the lowest cost: path
    length (m) plus ``turn_cost_m_per_rad`` times the turn toward it from ``heading_rad``.

    Only cells with at least ``min_unseen_cells`` unseen free cells in their 5 x 5
    neighbourhood count, so a lone unseen cell between seen ones is no reason to drive, and
    only those more than ``min_distance_cells`` of path away (the robot is already there).
    The ``previous`` goal, while it is still reachable, unseen and unblocked, is kept unless
    another costs at least ``switch_m`` less: two goals of about the same cost would otherwise
    take turns as the coverage grows, and a robot turning to each in turn reaches neither.
    """
    unseen_free = ~seen & ~blocked
    next_to_seen = np.zeros_like(seen)
    for dx, dy, _ in NEIGHBOURS:
        next_to_seen |= shifted(seen & ~blocked, dx, dy, False)
    unseen_around = np.zeros(seen.shape, int)
    for dx in range(-2, 3):
        for dy in range(-2, 3):
            unseen_around += shifted(unseen_free, dx, dy, False)
    candidates = (unseen_free & next_to_seen & np.isfinite(distance)
                  & (distance > min_distance_cells)
                  & (unseen_around >= min_unseen_cells))
    xs, ys = np.nonzero(candidates)
    if len(xs) == 0:
        return None

    def costs(xs, ys):
        """Costs in whole micrometres: cells whose costs are equal but for the last bits of
        the arctan2, sin and cos in their turns tie, and the first of them wins on every
        CPU."""
        bearings = np.arctan2(ys - robot_cell[1], xs - robot_cell[0]) - heading_rad
        turns = np.abs(np.arctan2(np.sin(bearings), np.cos(bearings)))
        return lattice(distance[xs, ys] * resolution_m + turn_cost_m_per_rad * turns)

    goal_costs = costs(xs, ys)
    best = int(np.argmin(goal_costs))
    if (previous is not None and 0 <= previous[0] < seen.shape[0]
            and 0 <= previous[1] < seen.shape[1] and unseen_free[previous]
            and np.isfinite(distance[previous]) and distance[previous] > min_distance_cells
            and goal_costs[best] > costs(np.array([previous[0]]), np.array([previous[1]]))[0]
            - lattice(switch_m)):
        return int(previous[0]), int(previous[1])
    return int(xs[best]), int(ys[best])


def segment_blocked(blocked: np.ndarray, start: Tuple[int, int], end: Tuple[int, int]) -> bool:
    """True when a blocked cell lies on the straight line between two cells (ends included)."""
    steps = max(abs(end[0] - start[0]), abs(end[1] - start[1])) * 2 + 1
    xs = np.rint(np.linspace(start[0], end[0], steps)).astype(int)
    ys = np.rint(np.linspace(start[1], end[1], steps)).astype(int)
    return bool(blocked[xs, ys].any())
