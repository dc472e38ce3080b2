"""Driving among obstacles: the robot's pose, its world map, paths to goals, frontier
exploration and the safety layer's inputs, for the can_stopper controller (pure, no ROS).

The navigator is fed the odom pose, range scans as points in base_link and the camera's floor
footprint, and keeps the world map (:mod:`can_seeker.control.costmap.world_map`) up to date;
it answers with commands that reach a goal on a grid path (:mod:`path_planner`) and with the
free travel that makes a command safe (:mod:`safety_inputs`: the live scans, the remembered
obstacles and the floor no sensor has observed).
"""
import math
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import numpy as np

from can_seeker.camera_geometry import CameraIntrinsics, CameraPose, floor_point
from can_seeker.control import avoidance, can_candidates
from can_seeker.control.costmap.world_map import WorldMap
from can_seeker.control.path_planner import PathPlanner
from can_seeker.control.reasons import Kind, Reason, reason
from can_seeker.control.safety_inputs import SafetyInputs

LOOKAHEAD_M = 0.5
MIN_LOOKAHEAD_M = 0.2
CLEAR_AHEAD_M = 0.3


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
    """The world map kept up to date and the motions built on it. Units: m, rad, s; poses in
    odom."""

    def __init__(self, resolution_m: float, size_m: float, robot_radius_m: float,
                 plan_margin_m: float, safety_margin_m: float, memory_s: float = np.inf,
                 unknown_wait_s: float = np.inf):
        self.world = WorldMap(resolution_m, size_m)
        self.robot_radius_m = robot_radius_m
        self.safety = SafetyInputs(self.world, robot_radius_m, safety_margin_m, memory_s,
                                   unknown_wait_s)
        self.paths = PathPlanner(self.world, robot_radius_m, plan_margin_m, self.cell_margin_m)
        self._pose: Optional[Pose2D] = None

    def reset(self) -> None:
        """Forget the map, the pose, the last scans and the places the can may stand."""
        self.world.clear()
        self._pose = None
        self.safety.last_scans = {}

    @property
    def pose(self) -> Optional[Pose2D]:
        """base_link in odom (None before the first odometry)."""
        return self._pose

    @pose.setter
    def pose(self, pose: Pose2D) -> None:
        """The robot is at ``pose``: the floor under its body is observed free."""
        self._pose = pose
        self.world.update_from_footprint((pose.x, pose.y), self.robot_radius_m)

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
        if source not in self.world.scan_s:
            self.world.update_from_footprint(origin[0], range_min_m + self.world.resolution_m)
        self.safety.last_scans[source] = (ends[hits], pose)
        if can_candidates.all_round(ends, origin_base):
            self.world.candidates.add(avoidance.from_frame(
                np.array(can_candidates.small_objects(ends, hits, origin_base)).reshape(-1, 2),
                pose.x, pose.y, pose.yaw))
        self.world.update_from_scan(origin[0], avoidance.from_frame(ends, pose.x, pose.y,
                                                                    pose.yaw),
                                    hits, range_min_m, stamp_s, source)

    def mark_seen(self, view: CameraView) -> None:
        """The camera covered its footprint from the current pose."""
        if self.pose is None:
            return
        pose = self.pose
        camera_xy = avoidance.from_frame(np.array((view.x, view.y)), pose.x, pose.y, pose.yaw)[0]
        self.world.update_from_camera(camera_xy, pose.yaw + view.yaw, view.half_fov_rad,
                                      view.near_m, view.far_m)

    @property
    def cell_margin_m(self) -> float:
        """The margin beyond ``robot_radius`` the safety layer keeps from remembered obstacles."""
        return self.safety.safety_margin_m + self.safety.cell_spread_m

    def obstacles_base(self, exclude_xy=None, exclude_radius_m: float = 0.0):
        """:meth:`SafetyInputs.obstacles_base` at the current pose."""
        return self.safety.obstacles_base(self.pose, exclude_xy, exclude_radius_m)

    def free_travel_m(self, command: Tuple[float, float], exclude_xy=None,
                      exclude_radius_m: float = 0.0, unknown: bool = True) -> float:
        """:meth:`SafetyInputs.free_travel_m` at the current pose."""
        return self.safety.free_travel_m(self.pose, command, exclude_xy, exclude_radius_m,
                                         unknown)

    def safety_block(self, command: Tuple[float, float], exclude_xy=None,
                     exclude_radius_m: float = 0.0) -> Tuple[float, Optional[np.ndarray]]:
        """:meth:`SafetyInputs.safety_block` at the current pose."""
        return self.safety.safety_block(self.pose, command, exclude_xy, exclude_radius_m)

    def free_travel_toward_m(self, targets_base: np.ndarray, exclude_xy=None,
                             exclude_radius_m: float = 0.0) -> np.ndarray:
        """:meth:`SafetyInputs.free_travel_toward_m` at the current pose."""
        return self.safety.free_travel_toward_m(self.pose, targets_base, exclude_xy,
                                                exclude_radius_m)

    def path_to(self, goal_xy: Sequence[float], exclude_xy=None, exclude_radius_m: float = 0.0,
                previous_xy: Optional[np.ndarray] = None) -> Optional[np.ndarray]:
        """:meth:`PathPlanner.path_to` from the current pose."""
        return self.paths.path_to(self.pose, goal_xy, exclude_xy, exclude_radius_m, previous_xy)

    def frontier(self, turn_cost_m_per_rad: float, min_unseen_cells: int,
                 previous_xy: Optional[Sequence[float]] = None) -> Optional[np.ndarray]:
        """:meth:`PathPlanner.frontier` from the current pose."""
        return self.paths.frontier(self.pose, turn_cost_m_per_rad, min_unseen_cells,
                                   previous_xy)

    def straight_line_blocked(self, goal_xy: Sequence[float], exclude_xy=None,
                              exclude_radius_m: float = 0.0) -> bool:
        """:meth:`PathPlanner.line_blocked` from the robot to ``goal_xy``."""
        return self.paths.line_blocked((self.pose.x, self.pose.y), goal_xy, exclude_xy,
                                       exclude_radius_m)

    def unviewed_candidate(self) -> Optional[np.ndarray]:
        """The nearest place an all-round scan showed a small free-standing object (see
        :mod:`can_seeker.control.can_candidates`) that the camera has not had in view, or
        None."""
        if self.pose is None:
            return None
        return self.world.candidates.nearest_unviewed(self.distance_to)

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
        index = self.paths.nearest_clear((pose.x, pose.y), path_xy, index, nearest)
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
