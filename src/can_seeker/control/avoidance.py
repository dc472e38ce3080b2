"""Never touch anything: forward speed limited by the free distance along the robot's path.

Obstacles are points on the floor in base_link (x forward, y left). The robot is a circle of
``radius_m`` about base_link, so turning in place can never hit anything it does not touch
already; driving, forward or backward, sweeps a corridor along the arc of the commanded
(linear, angular). The free travel is how far the robot can go along that arc before its circle,
grown by a margin, would touch a point (each point may carry its own clearance: a remembered
obstacle is one hit per map cell, the rest of it may stand nearer); the speed is capped so the
deceleration limit stops it within that distance.
"""
import math
from typing import Optional, Sequence, Tuple, Union

import numpy as np

ARC_STEP_M = 0.02
CLOSER_TOLERANCE_M = 1e-6
"""Rounding allowance (m) when checking that the robot comes no nearer to a point."""


def arc_poses(linear: float, angular: float, length_m: float) -> np.ndarray:
    """(x, y) of base_link after travelling 0, step, ... ``length_m`` along the arc of a
    (linear, angular) command, backward for a negative linear (M x 2, base_link at the
    start)."""
    travel = np.arange(0.0, length_m + 1e-9, ARC_STEP_M)
    direction = -1.0 if linear < 0.0 else 1.0
    curvature = angular / abs(linear) if abs(linear) > 1e-6 else 0.0
    if abs(curvature) < 1e-6:
        return np.stack((direction * travel, np.zeros_like(travel)), axis=-1)
    heading = curvature * travel
    return direction * np.stack((np.sin(heading) / curvature,
                                 (1.0 - np.cos(heading)) / curvature), axis=-1)


def free_travel_m(points: np.ndarray, linear: float, angular: float,
                  clearance_m: Union[float, np.ndarray], horizon_m: float) -> float:
    """How far base_link can move along the command's arc (m, up to ``horizon_m``) before a
    point comes within ``clearance_m`` of it (one value, or one per point). A point already
    within its clearance may not come any nearer: the robot may drive away from it, along
    it or around it, never toward it."""
    return first_block(points, linear, angular, clearance_m, horizon_m)[0]


def first_block(points: np.ndarray, linear: float, angular: float,
                clearance_m: Union[float, np.ndarray],
                horizon_m: float) -> Tuple[float, Optional[int]]:
    """(free travel m, index of the point that ends it or None) along the command's arc (see
    :func:`free_travel_m`)."""
    points = np.asarray(points, float).reshape(-1, 2)
    if len(points) == 0:
        return horizon_m, None
    touching = _touching(arc_poses(linear, angular, horizon_m), points, clearance_m)
    blocked = np.nonzero(touching.any(axis=1))[0]
    if len(blocked) == 0:
        return horizon_m, None
    first = int(blocked[0])
    return max(0.0, float(first - 1) * ARC_STEP_M), int(np.argmax(touching[first]))


def straight_free_travel_m(points: np.ndarray, headings_rad: np.ndarray,
                           clearance_m: Union[float, np.ndarray], horizon_m: float) -> np.ndarray:
    """:func:`free_travel_m` forward on the straight line of each of ``headings_rad``
    (base_link), as once the robot has turned in place to that heading, in one pass."""
    points = np.asarray(points, float).reshape(-1, 2)
    headings = np.asarray(headings_rad, float).reshape(-1)
    if len(points) == 0:
        return np.full(len(headings), horizon_m)
    travel = np.arange(0.0, horizon_m + 1e-9, ARC_STEP_M)
    poses = travel[None, :, None] * np.stack((np.cos(headings), np.sin(headings)),
                                             axis=-1)[:, None, :]
    blocked = _touching(poses, points, clearance_m).any(axis=-1)
    first = np.argmax(blocked, axis=1)
    return np.where(blocked.any(axis=1), np.maximum(0.0, (first - 1) * ARC_STEP_M), horizon_m)


def _touching(poses: np.ndarray, points: np.ndarray,
              clearance_m: Union[float, np.ndarray]) -> np.ndarray:
    """(..., M, N): base_link at pose m (``poses`` ..., M x 2) is nearer point n than it may
    come: its clearance, or where it already is within it, its distance now."""
    limit = (np.minimum(np.asarray(clearance_m, float), np.linalg.norm(points, axis=1))
             - CLOSER_TOLERANCE_M)
    squared = ((poses * poses).sum(axis=-1)[..., None] + (points * points).sum(axis=1)
               - 2.0 * poses @ points.T)
    return squared < np.where(limit > 0.0, limit * limit, -1.0)


def safe_linear(linear: float, free_m: float, decel_mps2: float, reserve_m: float) -> float:
    """Speed, forward or backward, capped so braking at ``decel_mps2`` stops ``reserve_m``
    short of ``free_m`` (the free travel in the direction of ``linear``); zero when either is
    not a number."""
    room_m = free_m - reserve_m
    if not (room_m > 0.0 and math.isfinite(linear)):
        return 0.0
    return math.copysign(min(abs(linear), math.sqrt(2.0 * decel_mps2 * room_m)), linear)


def far_from(points: np.ndarray, centre_xy: Sequence[float], radius_m: float) -> np.ndarray:
    """Which ``points`` lie farther than ``radius_m`` from ``centre_xy`` (the target the robot is
    meant to reach, which a range sensor sees like any obstacle)."""
    points = np.asarray(points, float).reshape(-1, 2)
    return np.linalg.norm(points - np.asarray(centre_xy, float), axis=1) > radius_m


def to_frame(points_xy: np.ndarray, x_m: float, y_m: float, yaw_rad: float) -> np.ndarray:
    """Points given in a parent frame, expressed in the child frame at pose (x, y, yaw)."""
    points_xy = np.asarray(points_xy, float).reshape(-1, 2)
    cos_yaw, sin_yaw = math.cos(yaw_rad), math.sin(yaw_rad)
    dx, dy = points_xy[:, 0] - x_m, points_xy[:, 1] - y_m
    return np.stack((cos_yaw * dx + sin_yaw * dy, -sin_yaw * dx + cos_yaw * dy), axis=-1)


def from_frame(points_xy: np.ndarray, x_m: float, y_m: float, yaw_rad: float) -> np.ndarray:
    """Points given in the child frame at pose (x, y, yaw), expressed in the parent frame."""
    points_xy = np.asarray(points_xy, float).reshape(-1, 2)
    cos_yaw, sin_yaw = math.cos(yaw_rad), math.sin(yaw_rad)
    return np.stack((x_m + cos_yaw * points_xy[:, 0] - sin_yaw * points_xy[:, 1],
                     y_m + sin_yaw * points_xy[:, 0] + cos_yaw * points_xy[:, 1]), axis=-1)


def wrap_angle(angle_rad: float) -> float:
    """``angle_rad`` in (-pi, pi]."""
    return math.atan2(math.sin(angle_rad), math.cos(angle_rad))


def steer_to_point(target_base: Tuple[float, float], cruise_mps: float, turn_in_place_rad: float,
                   angular_gain: float) -> Tuple[float, float]:
    """(linear, angular) that drives base_link toward a point in base_link: turn toward it,
    forward speed falling with the square of the bearing, to zero at ``turn_in_place_rad``
    off. A path's lookahead point lies a few degrees off the heading most of the time (the
    path turns, and is planned again as the map grows); a fall linear in the bearing crawled
    at two thirds of the cruise on those small corrections."""
    bearing = math.atan2(target_base[1], target_base[0])
    linear = cruise_mps * max(0.0, 1.0 - (bearing / turn_in_place_rad) ** 2)
    return linear, angular_gain * bearing


def lookahead_index(path_xy: np.ndarray, position_xy: Sequence[float],
                    lookahead_m: float) -> int:
    """Index of the first path point at least ``lookahead_m`` from ``position_xy`` after the
    path point nearest to it (the path's end when none is that far)."""
    path_xy = np.asarray(path_xy, float).reshape(-1, 2)
    distances = np.linalg.norm(path_xy - np.asarray(position_xy, float), axis=1)
    nearest = int(np.argmin(distances))
    ahead = np.nonzero(distances[nearest:] >= lookahead_m)[0]
    return nearest + int(ahead[0]) if len(ahead) else len(path_xy) - 1


def open_turn_sign(points: np.ndarray, fallback_sign: float) -> float:
    """+1 (left) or -1 (right): the side with fewer obstacle points ahead of the robot, so a
    blocked robot turns away from them; ``fallback_sign`` on a tie."""
    points = np.asarray(points, float).reshape(-1, 2)
    ahead = points[points[:, 0] > 0.0]
    left = int(np.sum(ahead[:, 1] > 0.0))
    right = int(np.sum(ahead[:, 1] < 0.0))
    if left == right:
        return fallback_sign
    return 1.0 if left < right else -1.0


def clear_heading(points: np.ndarray, target_rad: float, clearance_m: Union[float, np.ndarray],
                  needed_m: float, candidates: int = 24) -> float:
    """The heading (rad, base_link) nearest to ``target_rad`` along which the robot can drive
    straight for ``needed_m`` without coming within ``clearance_m`` (one value or one per
    point) of a point (a gap in the scan); NaN when every direction is blocked."""
    points = np.asarray(points, float).reshape(-1, 2)
    headings = np.concatenate(([target_rad], target_rad + np.linspace(
        -math.pi, math.pi, candidates, endpoint=False)[1:]))
    order = np.argsort(np.abs(np.arctan2(np.sin(headings - target_rad),
                                         np.cos(headings - target_rad))), kind='stable')
    for heading in headings[order]:
        rotated = to_frame(points, 0.0, 0.0, float(heading))
        if free_travel_m(rotated, 1.0, 0.0, clearance_m, needed_m) >= needed_m:
            return float(wrap_angle(heading))
    return math.nan
