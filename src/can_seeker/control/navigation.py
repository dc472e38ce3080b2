"""Driving among obstacles: the robot's pose, its obstacle and coverage grid, paths to goals,
frontier exploration and the safety layer, for the can_stopper controller (pure, no ROS).

The navigator is fed the odom pose, range scans as points in base_link and the camera's floor
footprint; it answers with commands that reach a goal on a grid path and with the same
command made safe (:func:`can_seeker.control.avoidance.safe_linear` on the free travel along
its arc through the live scan, the remembered obstacles and the floor no sensor has observed).
"""
import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from can_seeker.camera_geometry import CameraIntrinsics, CameraPose, floor_point
from can_seeker.control import avoidance, can_candidates, planner
from can_seeker.control.grid_map import GridMap
from can_seeker.control.reasons import Kind, Reason, reason
from can_seeker.lattice import lattice

PLAN_MARGIN_CELLS = 10
SAFETY_HORIZON_M = 1.0
MEMORY_RADIUS_M = 1.2
GOAL_REACHED_M = 0.25
LOOKAHEAD_M = 0.5
MIN_LOOKAHEAD_M = 0.2
CLEAR_AHEAD_M = 0.3
WAVEFRONTS_KEPT = 4
"""Wavefronts kept for plans through the same cells (one per margin, for paths and
exploration)."""
PATH_SWITCH_M = 0.5
"""A new path replaces a still clear one to the same goal only when it is this much shorter
(m), and a new exploration goal replaces one still unseen only when it costs this much less:
two ways about an obstacle of about the same length, or two goals, would otherwise take turns
as the map changes, and a robot turning to each in turn would reach neither."""


@dataclass(frozen=True)
class Pose2D:
    """A pose on the floor plane: position (m) and heading (rad) in its parent frame (base_link
    in odom; the camera in base_link)."""

    x: float
    y: float
    yaw: float


@dataclass(frozen=True)
class CameraView:
    """The floor the camera covers, in base_link: from (x, y) looking along ``yaw`` (rad),
    ``half_fov_rad`` either side, from ``near_m`` to ``far_m`` away on the floor.
    ``base_near_m`` is where the floor enters the image's bottom row, along ``yaw``: nearer, a
    target's base is below the image (0: unknown). The floor the image holds lies beyond that
    row's floor line and between the floor lines of its side columns, which cross it
    ``base_half_width_m`` either side of ``yaw`` and run out ``side_slope`` m wider per m
    farther (a pitched camera sees a trapezoid of floor, narrowest at the bottom row)."""

    x: float
    y: float
    yaw: float
    half_fov_rad: float
    near_m: float
    far_m: float
    base_near_m: float = 0.0
    base_half_width_m: float = math.inf
    side_slope: float = 0.0

    def back_up_to_see_m(self, point_base: Sequence[float], margin_m: float) -> float:
        """How far (m) the robot must back up straight for floor point ``point_base``
        (base_link) to lie ``margin_m`` inside the image's floor: past the bottom row's floor
        line and between the side columns' (0 when it does already, inf when no backing up
        brings it between them)."""
        dx, dy = point_base[0] - self.x, point_base[1] - self.y
        forward_m = dx * math.cos(self.yaw) + dy * math.sin(self.yaw)
        lateral_m = abs(-dx * math.sin(self.yaw) + dy * math.cos(self.yaw))
        needed_m = self.base_near_m + margin_m
        outside_m = lateral_m + margin_m - self.base_half_width_m
        if outside_m > 0.0:
            if self.side_slope <= 0.0:
                return math.inf
            needed_m += outside_m / self.side_slope
        return max(0.0, needed_m - forward_m)


def camera_view(pose: CameraPose, intrinsics: CameraIntrinsics, max_range_m: float,
                target_height_m: float) -> CameraView:
    """The camera's floor footprint for finding a target ``target_height_m`` tall: its
    horizontal field of view, from where the target's top enters the image's bottom row to
    where the top row meets the floor (at most ``max_range_m``, where the target is still
    found), measured from the camera's floor point."""
    half_fov = math.atan2(intrinsics.width / 2.0, intrinsics.fx)
    camera_xy = np.array(pose.position[:2], float)

    def floor_distance(v_px: float) -> Optional[float]:
        point = floor_point(pose, intrinsics, intrinsics.cx, v_px)
        return None if point is None else float(np.linalg.norm(np.array(point) - camera_xy))

    near = floor_distance(intrinsics.height - 1.0)
    far = floor_distance(0.0)
    far_m = max_range_m if far is None else min(far, max_range_m)
    near_m = 0.0
    if near is not None and pose.height_m > 0.0:
        near_m = near * max(0.0, 1.0 - target_height_m / pose.height_m)
    half_width_m, side_slope = _floor_sides(pose, intrinsics)
    return CameraView(float(camera_xy[0]), float(camera_xy[1]), pose.heading_rad, half_fov,
                      near_m, far_m, 0.0 if near is None else near, half_width_m, side_slope)


def _floor_sides(pose: CameraPose, intrinsics: CameraIntrinsics) -> Tuple[float, float]:
    """(half width m, slope) of the image's floor trapezoid (see :class:`CameraView`): the
    nearer to the heading of its two side columns' floor points on the bottom row, and the
    smaller growth of the two sides between that row and the one halfway up to the centre
    ((inf, 0) when the bottom row does not meet the floor)."""
    heading = pose.heading_rad
    along = np.array((math.cos(heading), math.sin(heading)))
    across = np.array((-math.sin(heading), math.cos(heading)))
    bottom_v = intrinsics.height - 1.0
    upper_v = (bottom_v + intrinsics.cy) / 2.0
    half_widths, slopes = [], []
    for u in (0.0, intrinsics.width - 1.0):
        near = floor_point(pose, intrinsics, u, bottom_v)
        if near is None:
            return math.inf, 0.0
        near_offset = np.array(near) - np.array(pose.position[:2], float)
        half_widths.append(abs(float(near_offset @ across)))
        far = floor_point(pose, intrinsics, u, upper_v)
        if far is None:
            slopes.append(0.0)
            continue
        step = np.array(far) - np.array(near)
        slopes.append(max(0.0, abs(float((near_offset + step) @ across)) - half_widths[-1])
                      / max(float(step @ along), 1e-9))
    return min(half_widths), min(slopes)


class Navigator:
    """Grid world model and the motions built on it. Units: m, rad, s; poses in odom."""

    def __init__(self, resolution_m: float, size_m: float, robot_radius_m: float,
                 plan_margin_m: float, safety_margin_m: float, memory_s: float = np.inf,
                 unknown_wait_s: float = np.inf):
        self.grid = GridMap(resolution_m, size_m)
        self.memory_s = memory_s
        self.unknown_wait_s = unknown_wait_s
        self.robot_radius_m = robot_radius_m
        self.plan_margin_m = plan_margin_m
        self.safety_margin_m = safety_margin_m
        self.candidate_reach_m = can_candidates.MAX_WIDTH_M / 2.0 + resolution_m * math.sqrt(2.0)
        """Remembered obstacle cells reaching this near a place where the can may stand may be
        its own (the scans' returns from the can, each within half the widest run of the place,
        in a cell up to a diagonal across): they do not hide it from the camera. Giving up a
        goal this near gives up the place."""
        self._pose: Optional[Pose2D] = None
        self.last_scans: Dict[str, Tuple[np.ndarray, Pose2D]] = {}
        self.candidates: List[np.ndarray] = []
        self.candidates_viewed: List[bool] = []
        self._keep_off_memo: Tuple = (None, None)
        self._wavefronts: Dict[Tuple, np.ndarray] = {}

    def reset(self) -> None:
        """Forget the map, the pose, the last scans and the places the can may stand."""
        self.grid.clear()
        self._pose = None
        self.last_scans = {}
        self.candidates = []
        self.candidates_viewed = []

    @property
    def pose(self) -> Optional[Pose2D]:
        """base_link in odom (None before the first odometry)."""
        return self._pose

    @pose.setter
    def pose(self, pose: Pose2D) -> None:
        """The robot is at ``pose``: the floor under its body is observed free."""
        self._pose = pose
        self.grid.mark_observed((pose.x, pose.y), self.robot_radius_m)

    def add_scan(self, ends_base: np.ndarray, hits: np.ndarray, origin_base: Sequence[float],
                 pose: Pose2D, range_min_m: float = 0.0, stamp_s: float = 0.0,
                 source: str = '') -> None:
        """One range scan of sensor ``source`` taken at ``pose``: the end of every ray in
        base_link (N x 2), where ``hits`` marks a return (else the ray ends at the range it
        vouches for), from the sensor at ``origin_base``, which is blind nearer than
        ``range_min_m``, at ``stamp_s``. Each sensor's last scan is kept: what any of them
        sees is an obstacle. The robot starts on free floor: a sensor's first scan counts its
        blind zone as observed (no sensor could ever observe it from the start pose)."""
        ends = np.asarray(ends_base, float).reshape(-1, 2)
        hits = np.asarray(hits, bool).reshape(-1)
        origin = avoidance.from_frame(np.asarray(origin_base, float), pose.x, pose.y, pose.yaw)
        if source not in self.grid.scan_s:
            self.grid.mark_observed(origin[0], range_min_m + self.grid.resolution_m)
        self.last_scans[source] = (ends[hits], pose)
        if can_candidates.all_round(ends, origin_base):
            self._add_candidates(avoidance.from_frame(
                np.array(can_candidates.small_objects(ends, hits, origin_base)).reshape(-1, 2),
                pose.x, pose.y, pose.yaw))
        self.grid.add_scan(origin[0], avoidance.from_frame(ends, pose.x, pose.y, pose.yaw), hits,
                           range_min_m, stamp_s, source)

    def mark_seen(self, view: CameraView) -> None:
        """The camera covered its footprint from the current pose."""
        if self.pose is None:
            return
        pose = self.pose
        camera_xy = avoidance.from_frame(np.array((view.x, view.y)), pose.x, pose.y, pose.yaw)[0]
        self.grid.mark_seen(camera_xy, pose.yaw + view.yaw, view.half_fov_rad, view.near_m,
                            view.far_m)
        for index, point in enumerate(self.candidates):
            if not self.candidates_viewed[index] and self._in_view(point, camera_xy,
                                                                   pose.yaw + view.yaw, view):
                self.candidates_viewed[index] = True

    def _in_view(self, point: np.ndarray, camera_xy: np.ndarray, heading_rad: float,
                 view: CameraView) -> bool:
        """True when a can standing at odom ``point`` is in the camera's view: within its
        field of view, from ``near_m`` (its top enters the bottom row) to ``far_m``, with no
        remembered obstacle on the line of sight short of :attr:`candidate_reach_m` from it
        (compared on the lattice of :mod:`can_seeker.lattice`: a can right at the view's edge
        is in it or not whatever the last bits of the arctan2 that place it and the edge)."""
        offset = point - camera_xy
        distance = float(np.hypot(*offset))
        bearing = avoidance.wrap_angle(math.atan2(offset[1], offset[0]) - heading_rad)
        near_um, distance_um, far_um = lattice((view.near_m, distance, view.far_m))
        if not (near_um <= distance_um <= far_um
                and lattice(abs(bearing)) <= lattice(view.half_fov_rad)):
            return False
        along = np.arange(0.0, max(0.0, distance - self.candidate_reach_m),
                          self.grid.resolution_m / 2.0)
        ix, iy, inside = self.grid.index_of(camera_xy + along[:, None] * offset / distance)
        return not bool(self.grid.occupied_at(ix[inside], iy[inside]).any())

    @property
    def cell_spread_m(self) -> float:
        """How much nearer (m) than a remembered cell's one hit point the rest of the obstacle
        in that cell may stand: half a cell diagonal (the part of a surface that the sensor saw
        from elsewhere, or hardly at all, before it left the view)."""
        return self.grid.resolution_m / math.sqrt(2.0)

    @property
    def cell_margin_m(self) -> float:
        """The margin beyond ``robot_radius`` the safety layer keeps from remembered obstacles."""
        return self.safety_margin_m + self.cell_spread_m

    def obstacles_base(self, exclude_xy: Optional[Sequence[float]] = None,
                       exclude_radius_m: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
        """(points N x 2 in base_link now, clearance m each) of what the robot must keep away
        from: each sensor's last scan (moved by the motion since; ``robot_radius`` +
        ``safety_margin``)
        and the remembered obstacle cells around the robot (where each was hit, the clearance
        grown by :attr:`cell_spread_m`), without those near ``exclude_xy`` (odom). A remembered
        obstacle out of the sensor's view stays until a scan sees its place free; one that
        scans have had in their blind zone for ``memory_s`` is dropped (there no ray can clear
        a phantom, which would otherwise block the robot for ever)."""
        pose = self.pose
        if pose is None:
            return np.zeros((0, 2)), np.zeros(0)
        clearance_m = self.robot_radius_m + self.safety_margin_m
        cells = self.grid.obstacle_points((pose.x, pose.y), MEMORY_RADIUS_M, self.memory_s)
        points, clearances = [cells], [np.full(len(cells), clearance_m + self.cell_spread_m)]
        for scan_points, scan in self.last_scans.values():
            points.append(avoidance.from_frame(scan_points, scan.x, scan.y, scan.yaw))
            clearances.append(np.full(len(scan_points), clearance_m))
        odom_points, clearance = np.concatenate(points), np.concatenate(clearances)
        if exclude_xy is not None:
            keep = avoidance.far_from(odom_points, exclude_xy, exclude_radius_m)
            odom_points, clearance = odom_points[keep], clearance[keep]
        return avoidance.to_frame(odom_points, pose.x, pose.y, pose.yaw), clearance

    def unknown_base(self, exclude_xy: Optional[Sequence[float]] = None,
                     exclude_radius_m: float = 0.0) -> Tuple[np.ndarray, float]:
        """(points N x 2 in base_link now, clearance m) of the unknown cells around the robot
        (see :meth:`GridMap.unknown_points`), without those near ``exclude_xy`` (odom): an
        obstacle may stand anywhere in one, so the robot keeps ``robot_radius`` plus half a
        (fine) cell diagonal from its centre."""
        pose = self.pose
        if pose is None:
            return np.zeros((0, 2)), 0.0
        points = self.grid.unknown_points((pose.x, pose.y), MEMORY_RADIUS_M,
                                          self.unknown_wait_s, self.memory_s)
        if exclude_xy is not None:
            points = points[avoidance.far_from(points, exclude_xy, exclude_radius_m)]
        return (avoidance.to_frame(points, pose.x, pose.y, pose.yaw),
                self.robot_radius_m + self.grid.observed_resolution_m / math.sqrt(2.0))

    def free_travel_m(self, command: Tuple[float, float], exclude_xy=None,
                      exclude_radius_m: float = 0.0, unknown: bool = True) -> float:
        """Free travel along the command's arc (m, up to the safety horizon), short of the
        obstacles and, unless ``unknown`` is false, of the floor no sensor has observed."""
        if unknown:
            return self.safety_block(command, exclude_xy, exclude_radius_m)[0]
        points, clearance = self.obstacles_base(exclude_xy, exclude_radius_m)
        return avoidance.free_travel_m(points, command[0], command[1], clearance,
                                       SAFETY_HORIZON_M)

    def safety_block(self, command: Tuple[float, float], exclude_xy=None,
                     exclude_radius_m: float = 0.0) -> Tuple[float, Optional[np.ndarray]]:
        """(free travel m along the command's arc, short of obstacles and unknown floor; the
        unknown floor point in base_link that ends it, None when an obstacle or nothing does),
        in one pass."""
        points, clearance, obstacles = self._keep_off(exclude_xy, exclude_radius_m)
        travel_m, index = avoidance.first_block(points, command[0], command[1], clearance,
                                                SAFETY_HORIZON_M)
        if index is None or index < obstacles:
            return travel_m, None
        return travel_m, points[index].copy()

    def free_travel_toward_m(self, targets_base: np.ndarray, exclude_xy=None,
                             exclude_radius_m: float = 0.0) -> np.ndarray:
        """Free travel (m, up to the safety horizon) on the straight line from base_link toward
        each of ``targets_base`` (N x 2, base_link), as the safety layer counts it once the
        robot has turned in place to face that target (turning is never limited): short of
        the obstacles and of the floor no sensor has observed."""
        targets = np.asarray(targets_base, float).reshape(-1, 2)
        points, clearance, _ = self._keep_off(exclude_xy, exclude_radius_m)
        return avoidance.straight_free_travel_m(points, np.arctan2(targets[:, 1], targets[:, 0]),
                                                clearance, SAFETY_HORIZON_M)

    def _keep_off(self, exclude_xy, exclude_radius_m: float) -> Tuple[np.ndarray, np.ndarray,
                                                                       int]:
        """(points N x 2 in base_link, clearance m each, how many of them are obstacles) that
        the safety layer keeps the robot from: the obstacles first, then the unknown floor.
        The last answer is kept while the pose, the map and the exclusion stay the same (the
        checks of one tick ask several times)."""
        key = (self.pose, self.grid.changes, None if exclude_xy is None
               else tuple(float(v) for v in exclude_xy), exclude_radius_m)
        if self._keep_off_memo[0] != key:
            self._keep_off_memo = key, self._points_to_keep_off(exclude_xy, exclude_radius_m)
        return self._keep_off_memo[1]

    def _points_to_keep_off(self, exclude_xy, exclude_radius_m: float) -> Tuple[np.ndarray,
                                                                                 np.ndarray, int]:
        """:meth:`_keep_off`, computed."""
        points, clearance = self.obstacles_base(exclude_xy, exclude_radius_m)
        unknown_points, unknown_clearance = self.unknown_base(exclude_xy, exclude_radius_m)
        return (np.concatenate((points, unknown_points)),
                np.concatenate((clearance, np.full(len(unknown_points), unknown_clearance))),
                len(points))

    def blocked_cells(self, exclude_xy=None, exclude_radius_m: float = 0.0,
                      margin_m: Optional[float] = None) -> np.ndarray:
        """Cells the robot's centre must not enter: obstacles grown by radius plus margin."""
        occupied = self.grid.occupied()
        if exclude_xy is not None:
            ix, iy = np.nonzero(occupied)
            centres = self.grid.centre_of(ix, iy).reshape(-1, 2)
            near = np.linalg.norm(centres - np.asarray(exclude_xy, float), axis=1) \
                <= exclude_radius_m
            occupied = occupied.copy()
            occupied[ix[near], iy[near]] = False
        margin = self.plan_margin_m if margin_m is None else margin_m
        return planner.inflate(occupied, (self.robot_radius_m + margin) / self.grid.resolution_m)

    def _plan(self, goal: Optional[Tuple[int, int]], exclude_xy, exclude_radius_m: float,
              margin_m: float):
        """(window, blocked cells, wavefront distances) from the robot's cell with obstacles
        grown by ``margin_m``. A robot that already stands within the margin may cross the
        cells about it that the margin alone blocks, so it can leave; elsewhere the margin
        holds."""
        start = self.grid.cell_of(self.pose.x, self.pose.y)
        if start is None:
            return None
        known = self.grid.seen | self.grid.occupied()
        cells = (start,) if goal is None else (start, goal)
        window = planner.planning_window(known, cells, PLAN_MARGIN_CELLS)
        local_start = window.local(start)
        blocked = window.crop(self.blocked_cells(exclude_xy, exclude_radius_m, margin_m))
        if blocked[local_start]:
            about = np.zeros_like(blocked)
            about[local_start] = True
            about = planner.inflate(about, (self.robot_radius_m + margin_m)
                                    / self.grid.resolution_m)
            bare = window.crop(self.blocked_cells(exclude_xy, exclude_radius_m, 0.0))
            blocked &= ~(about & ~bare)
        return window, blocked, self._wavefront(blocked, local_start)

    def _wavefront(self, blocked: np.ndarray, start: Tuple[int, int]) -> np.ndarray:
        """:func:`planner.wavefront` through the cells not ``blocked`` from ``start``
        (read-only); the last few are kept, as between two changes of the map the paths, the
        frontier and each margin plan through the same cells again."""
        key = (blocked.shape, start, np.packbits(blocked).tobytes())
        distance = self._wavefronts.pop(key, None)
        if distance is None:
            distance = planner.wavefront(~blocked, start)
            distance.flags.writeable = False
        self._wavefronts[key] = distance
        while len(self._wavefronts) > WAVEFRONTS_KEPT:
            del self._wavefronts[next(iter(self._wavefronts))]
        return distance

    @property
    def plan_margins_m(self) -> Tuple[float, ...]:
        """The margins a plan tries in turn: ``plan_margin``, then the safety layer's own (a
        passage too narrow for the planner's margin that the safety layer lets the robot
        through, such as a doorway, is still a way)."""
        return tuple(dict.fromkeys((self.plan_margin_m, min(self.plan_margin_m,
                                                             self.cell_margin_m))))

    def path_to(self, goal_xy: Sequence[float], exclude_xy=None,
                exclude_radius_m: float = 0.0,
                previous_xy: Optional[np.ndarray] = None) -> Optional[np.ndarray]:
        """Odom points of a grid path from the robot to ``goal_xy``, or None if unreachable
        (with each of :attr:`plan_margins_m` in turn). The rest of ``previous_xy``, the path
        followed so far, is kept while it still ends in the goal's cell, crosses no blocked
        cell and is at most :data:`PATH_SWITCH_M` longer than the new path."""
        goal = self.grid.cell_of(goal_xy[0], goal_xy[1])
        if self.pose is None or goal is None:
            return None
        for margin_m in self.plan_margins_m:
            plan = self._plan(goal, exclude_xy, exclude_radius_m, margin_m)
            if plan is None:
                return None
            window, blocked, distance = plan
            local_goal = window.local(goal)
            if np.isfinite(distance[local_goal]):
                kept = self._rest_if_clear(previous_xy, goal, window, blocked)
                if kept is not None and (self._length_from_robot(kept)
                                         <= distance[local_goal] * self.grid.resolution_m
                                         + PATH_SWITCH_M):
                    return kept
                cells = [window.grid(cell) for cell in planner.descend(distance, local_goal)]
                return self.grid.centre_of(*np.array(cells).T).reshape(-1, 2)
        return None

    def _rest_if_clear(self, path_xy: Optional[np.ndarray], goal: Tuple[int, int],
                       window: planner.Window, blocked: np.ndarray) -> Optional[np.ndarray]:
        """The part of ``path_xy`` from its point nearest the robot on, if the path ends in
        cell ``goal`` and that part crosses no ``blocked`` cell of ``window``; else None."""
        if path_xy is None or len(path_xy) == 0 or self.grid.cell_of(*path_xy[-1]) != goal:
            return None
        nearest = int(np.argmin(np.linalg.norm(path_xy - (self.pose.x, self.pose.y), axis=1)))
        rest = path_xy[nearest:]
        ix, iy, inside = self.grid.index_of(rest)
        lx, ly = ix - window.x0, iy - window.y0
        if not inside.all() or np.any((lx < 0) | (ly < 0) | (lx >= blocked.shape[0])
                                      | (ly >= blocked.shape[1])):
            return None
        return None if blocked[lx, ly].any() else rest

    def _length_from_robot(self, path_xy: np.ndarray) -> float:
        """Length (m) from the robot along ``path_xy``."""
        legs = np.diff(np.vstack(((self.pose.x, self.pose.y), path_xy)), axis=0)
        return float(np.hypot(legs[:, 0], legs[:, 1]).sum())

    def frontier(self, turn_cost_m_per_rad: float, min_unseen_cells: int,
                 previous_xy: Optional[Sequence[float]] = None) -> Optional[np.ndarray]:
        """Odom centre of the best exploration goal (see :func:`planner.frontier_goal`), with
        each of :attr:`plan_margins_m` in turn; the ``previous_xy`` goal is kept unless another
        costs at least :data:`PATH_SWITCH_M` less."""
        if self.pose is None:
            return None
        previous = None if previous_xy is None else self.grid.cell_of(*previous_xy)
        for margin_m in self.plan_margins_m:
            plan = self._plan(None, None, 0.0, margin_m)
            if plan is None:
                return None
            window, blocked, distance = plan
            start = window.local(self.grid.cell_of(self.pose.x, self.pose.y))
            goal = planner.frontier_goal(distance, window.crop(self.grid.seen), blocked, start,
                                         self.pose.yaw, self.grid.resolution_m,
                                         turn_cost_m_per_rad, min_unseen_cells,
                                         2.0 * GOAL_REACHED_M / self.grid.resolution_m,
                                         None if previous is None else window.local(previous),
                                         PATH_SWITCH_M)
            if goal is not None:
                return self.grid.centre_of(*window.grid(goal))
        return None

    def is_seen(self, xy: Sequence[float]) -> bool:
        """True when the camera has covered the cell of odom point ``xy``."""
        cell = self.grid.cell_of(xy[0], xy[1])
        return cell is None or bool(self.grid.seen[cell])

    def _add_candidates(self, points_xy: np.ndarray) -> None:
        """Remember the odom places where the can may stand, once each (within a cell)."""
        for point in points_xy:
            if all(np.linalg.norm(point - known) > self.grid.resolution_m
                   for known in self.candidates):
                self.candidates.append(point)
                self.candidates_viewed.append(self.grid.cell_of(*point) is None)

    def candidate_viewed(self, xy: Sequence[float]) -> bool:
        """True when the camera has had the remembered place ``xy`` in view (see
        :meth:`mark_seen`), or it is no remembered place."""
        for point, viewed in zip(self.candidates, self.candidates_viewed):
            if np.array_equal(point, xy):
                return viewed
        return True

    def unviewed_candidate(self) -> Optional[np.ndarray]:
        """The nearest place an all-round scan showed a small free-standing object (see
        :mod:`can_seeker.control.can_candidates`) that the camera has not had in view, or
        None."""
        if self.pose is None:
            return None
        waiting = [point for point, viewed in zip(self.candidates, self.candidates_viewed)
                   if not viewed]
        if not waiting:
            return None
        return min(waiting, key=self.distance_to)

    def give_up_on(self, xy: Sequence[float]) -> None:
        """Count the cells around an unreachable goal as seen, and any place the can may stand
        there as viewed, so exploration moves on."""
        cell = self.grid.cell_of(xy[0], xy[1])
        if cell is not None:
            self.grid.seen[max(0, cell[0] - 2):cell[0] + 3, max(0, cell[1] - 2):cell[1] + 3] = True
        for index, point in enumerate(self.candidates):
            if np.linalg.norm(point - np.asarray(xy, float)) <= self.candidate_reach_m:
                self.candidates_viewed[index] = True

    def straight_line_blocked(self, goal_xy: Sequence[float], exclude_xy=None,
                              exclude_radius_m: float = 0.0) -> bool:
        """True when the straight line from the robot to ``goal_xy`` crosses obstacles grown as
        the safety layer grows remembered ones (the robot's own cell aside)."""
        start = self.grid.cell_of(self.pose.x, self.pose.y)
        goal = self.grid.cell_of(goal_xy[0], goal_xy[1])
        if start is None or goal is None:
            return False
        blocked = self.blocked_cells(exclude_xy, exclude_radius_m, self.cell_margin_m)
        blocked[start] = False
        return planner.segment_blocked(blocked, start, goal)

    def follow(self, path_xy: np.ndarray, cruise_mps: float, turn_in_place_rad: float,
               angular_gain: float) -> Tuple[Tuple[float, float], Optional[Reason]]:
        """((linear, angular), why) toward the path's lookahead point, brought nearer along the
        path (down to ``MIN_LOOKAHEAD_M``) until the straight line to it clears the obstacles,
        so the robot does not cut corners into them; then the clear heading nearest to it, so a
        robot that has come too close to an obstacle turns to a gap instead of stalling.
        ``why`` says why it only turns (None when it drives)."""
        pose = self.pose
        index = avoidance.lookahead_index(path_xy, (pose.x, pose.y), LOOKAHEAD_M)
        nearest = avoidance.lookahead_index(path_xy, (pose.x, pose.y), MIN_LOOKAHEAD_M)
        start = self.grid.cell_of(pose.x, pose.y)
        if start is not None:
            blocked = self.blocked_cells(margin_m=self.cell_margin_m)
            blocked[start] = False
            for candidate in range(index, nearest - 1, -1):
                goal = self.grid.cell_of(*path_xy[candidate])
                if goal is not None and not planner.segment_blocked(blocked, start, goal):
                    index = candidate
                    break
        target_base = avoidance.to_frame(path_xy[index], pose.x, pose.y, pose.yaw)[0]
        points, clearance = self.obstacles_base()
        heading = avoidance.clear_heading(points, math.atan2(target_base[1], target_base[0]),
                                          clearance, CLEAR_AHEAD_M)
        if math.isnan(heading):
            return (0.0, math.copysign(angular_gain, target_base[1] or 1.0)), reason(
                Kind.NO_CLEAR_HEADING, clear_m=CLEAR_AHEAD_M)
        command = avoidance.steer_to_point((math.cos(heading), math.sin(heading)), cruise_mps,
                                           turn_in_place_rad, angular_gain)
        why = None if command[0] > 0.0 else reason(
            Kind.TURNING_TO_PATH, heading_deg=math.degrees(heading),
            limit_deg=math.degrees(turn_in_place_rad))
        return command, why

    def distance_to(self, xy: Sequence[float]) -> float:
        """Distance (m) from base_link to odom point ``xy``."""
        return math.hypot(xy[0] - self.pose.x, xy[1] - self.pose.y)
