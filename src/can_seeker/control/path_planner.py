"""Grid paths and exploration goals on the world map, for the navigator (pure, no ROS).

Obstacles are grown by the robot's radius plus a margin, tried in turn: ``plan_margin``, then
the safety layer's own (a doorway too narrow for the first is still a way). Distances come
from :func:`planner.wavefront` over the known part of the map; the last few are kept, as
between two changes of the map the paths, the frontier and each margin plan through the same
cells again. Design and reasons: docs/design/controller-and-safety.md.
"""
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from can_seeker.control import planner
from can_seeker.control.costmap.world_map import WorldMap

PLAN_MARGIN_CELLS = 10
GOAL_REACHED_M = 0.25
WAVEFRONTS_KEPT = 4
"""Wavefronts kept for plans through the same cells (one per margin, for paths and
exploration)."""
PATH_SWITCH_M = 0.5
"""A new path replaces a still clear one to the same goal only when it is this much shorter
(m), and a new exploration goal replaces one still unseen only when it costs this much less:
two ways about an obstacle of about the same length, or two goals, would otherwise take turns
as the map changes, and a robot turning to each in turn would reach neither."""


class PathPlanner:
    """Paths and frontier goals for a round robot of ``robot_radius_m`` on ``world``; poses
    (x, y, yaw) in odom."""

    def __init__(self, world: WorldMap, robot_radius_m: float, plan_margin_m: float,
                 cell_margin_m: float):
        self.world = world
        self.robot_radius_m = robot_radius_m
        self.plan_margin_m = plan_margin_m
        self.cell_margin_m = cell_margin_m
        self._wavefronts: Dict[Tuple, np.ndarray] = {}

    def blocked_cells(self, exclude_xy=None, exclude_radius_m: float = 0.0,
                      margin_m: Optional[float] = None) -> np.ndarray:
        """Cells the robot's centre must not enter: obstacles grown by radius plus margin
        (``plan_margin`` when None)."""
        margin = self.plan_margin_m if margin_m is None else margin_m
        return self.world.blocked_cells(self.robot_radius_m + margin, exclude_xy,
                                        exclude_radius_m)

    @property
    def plan_margins_m(self) -> Tuple[float, ...]:
        """The margins a plan tries in turn: ``plan_margin``, then the safety layer's own."""
        return tuple(dict.fromkeys((self.plan_margin_m, min(self.plan_margin_m,
                                                             self.cell_margin_m))))

    def _plan(self, pose, goal: Optional[Tuple[int, int]], exclude_xy, exclude_radius_m: float,
              margin_m: float):
        """(window, blocked cells, wavefront distances) from the robot's cell with obstacles
        grown by ``margin_m``. A robot that already stands within the margin may cross the
        cells about it that the margin alone blocks, so it can leave; elsewhere the margin
        holds."""
        start = self.world.cell_of(pose.x, pose.y)
        if start is None:
            return None
        cells = (start,) if goal is None else (start, goal)
        window = planner.planning_window(self.world.known(), cells, PLAN_MARGIN_CELLS)
        local_start = window.local(start)
        blocked = window.crop(self.blocked_cells(exclude_xy, exclude_radius_m, margin_m))
        if blocked[local_start]:
            about = np.zeros_like(blocked)
            about[local_start] = True
            about = planner.inflate(about, (self.robot_radius_m + margin_m)
                                    / self.world.resolution_m)
            bare = window.crop(self.blocked_cells(exclude_xy, exclude_radius_m, 0.0))
            blocked &= ~(about & ~bare)
        return window, blocked, self._wavefront(blocked, local_start)

    def _wavefront(self, blocked: np.ndarray, start: Tuple[int, int]) -> np.ndarray:
        """:func:`planner.wavefront` through the cells not ``blocked`` from ``start``
        (read-only), one of the last :data:`WAVEFRONTS_KEPT` when it planned the same."""
        key = (blocked.shape, start, np.packbits(blocked).tobytes())
        distance = self._wavefronts.pop(key, None)
        if distance is None:
            distance = planner.wavefront(~blocked, start)
            distance.flags.writeable = False
        self._wavefronts[key] = distance
        while len(self._wavefronts) > WAVEFRONTS_KEPT:
            del self._wavefronts[next(iter(self._wavefronts))]
        return distance

    def path_to(self, pose, goal_xy: Sequence[float], exclude_xy=None,
                exclude_radius_m: float = 0.0,
                previous_xy: Optional[np.ndarray] = None) -> Optional[np.ndarray]:
        """Odom points of a grid path from ``pose`` to ``goal_xy``, or None if unreachable
        (with each of :attr:`plan_margins_m` in turn). The rest of ``previous_xy``, the path
        followed so far, is kept while it still ends in the goal's cell, crosses no blocked
        cell and is at most :data:`PATH_SWITCH_M` longer than the new path."""
        goal = self.world.cell_of(goal_xy[0], goal_xy[1])
        if pose is None or goal is None:
            return None
        for margin_m in self.plan_margins_m:
            plan = self._plan(pose, goal, exclude_xy, exclude_radius_m, margin_m)
            if plan is None:
                return None
            window, blocked, distance = plan
            local_goal = window.local(goal)
            if np.isfinite(distance[local_goal]):
                kept = self._rest_if_clear(pose, previous_xy, goal, window, blocked)
                if kept is not None and (_length_from(pose, kept)
                                         <= distance[local_goal] * self.world.resolution_m
                                         + PATH_SWITCH_M):
                    return kept
                cells = [window.grid(cell) for cell in planner.descend(distance, local_goal)]
                return self.world.centre_of(*np.array(cells).T).reshape(-1, 2)
        return None

    def _rest_if_clear(self, pose, path_xy: Optional[np.ndarray], goal: Tuple[int, int],
                       window: planner.Window, blocked: np.ndarray) -> Optional[np.ndarray]:
        """The part of ``path_xy`` from its point nearest ``pose`` on, if the path ends in
        cell ``goal`` and that part crosses no ``blocked`` cell of ``window``; else None."""
        if path_xy is None or len(path_xy) == 0 or self.world.cell_of(*path_xy[-1]) != goal:
            return None
        nearest = int(np.argmin(np.linalg.norm(path_xy - (pose.x, pose.y), axis=1)))
        rest = path_xy[nearest:]
        ix, iy, inside = self.world.index_of(rest)
        lx, ly = ix - window.x0, iy - window.y0
        if not inside.all() or np.any((lx < 0) | (ly < 0) | (lx >= blocked.shape[0])
                                      | (ly >= blocked.shape[1])):
            return None
        return None if blocked[lx, ly].any() else rest

    def frontier(self, pose, turn_cost_m_per_rad: float, min_unseen_cells: int,
                 previous_xy: Optional[Sequence[float]] = None) -> Optional[np.ndarray]:
        """Odom centre of the best exploration goal from ``pose`` (see
        :func:`planner.frontier_goal`), with each of :attr:`plan_margins_m` in turn; the
        ``previous_xy`` goal is kept unless another costs at least :data:`PATH_SWITCH_M`
        less."""
        if pose is None:
            return None
        world = self.world
        previous = None if previous_xy is None else world.cell_of(*previous_xy)
        for margin_m in self.plan_margins_m:
            plan = self._plan(pose, None, None, 0.0, margin_m)
            if plan is None:
                return None
            window, blocked, distance = plan
            start = window.local(world.cell_of(pose.x, pose.y))
            goal = planner.frontier_goal(distance, window.crop(world.seen_cells()), blocked,
                                         start, pose.yaw, world.resolution_m,
                                         turn_cost_m_per_rad, min_unseen_cells,
                                         2.0 * GOAL_REACHED_M / world.resolution_m,
                                         None if previous is None else window.local(previous),
                                         PATH_SWITCH_M)
            if goal is not None:
                return world.centre_of(*window.grid(goal))
        return None

    def line_blocked(self, start_xy: Sequence[float], goal_xy: Sequence[float], exclude_xy=None,
                     exclude_radius_m: float = 0.0) -> bool:
        """True when the straight line from ``start_xy`` to ``goal_xy`` crosses obstacles grown
        as the safety layer grows remembered ones (the start's own cell aside)."""
        start = self.world.cell_of(start_xy[0], start_xy[1])
        goal = self.world.cell_of(goal_xy[0], goal_xy[1])
        if start is None or goal is None:
            return False
        blocked = self.blocked_cells(exclude_xy, exclude_radius_m, self.cell_margin_m)
        blocked[start] = False
        return planner.segment_blocked(blocked, start, goal)

    def nearest_clear(self, start_xy: Sequence[float], path_xy: np.ndarray, first: int,
                      last: int) -> int:
        """The first of the path's points from index ``first`` back to ``last`` that the
        straight line from ``start_xy`` reaches clear of the obstacles grown as the safety
        layer grows them (the start's own cell aside), else ``first``."""
        start = self.world.cell_of(start_xy[0], start_xy[1])
        if start is None:
            return first
        blocked = self.blocked_cells(margin_m=self.cell_margin_m)
        blocked[start] = False
        for candidate in range(first, last - 1, -1):
            goal = self.world.cell_of(*path_xy[candidate])
            if goal is not None and not planner.segment_blocked(blocked, start, goal):
                return candidate
        return first


def _length_from(pose, path_xy: np.ndarray) -> float:
    """Length (m) from ``pose`` along ``path_xy``."""
    legs = np.diff(np.vstack(((pose.x, pose.y), path_xy)), axis=0)
    return float(np.hypot(legs[:, 0], legs[:, 1]).sum())
