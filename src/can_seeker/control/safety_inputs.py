"""What the safety layer keeps the robot from, in base_link now, and the free travel short of
it (pure, no ROS): each sensor's last scan moved with the odometry since, the world map's
remembered obstacles and its unknown floor near the robot. Design and reasons:
docs/design/controller-and-safety.md.
"""
import math
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from can_seeker.control import avoidance
from can_seeker.control.costmap.world_map import WorldMap

SAFETY_HORIZON_M = 1.0
MEMORY_RADIUS_M = 1.2


class SafetyInputs:
    """Points to keep off for a round robot of ``robot_radius_m`` on ``world``, each with its
    clearance; poses (x, y, yaw) in odom. Remembered obstacles that scans have had in their
    blind zone for ``memory_s`` are dropped, and unknown floor in their blind disc for
    ``unknown_wait_s`` is taken for floor."""

    def __init__(self, world: WorldMap, robot_radius_m: float, safety_margin_m: float,
                 memory_s: float, unknown_wait_s: float):
        self.world = world
        self.robot_radius_m = robot_radius_m
        self.safety_margin_m = safety_margin_m
        self.memory_s = memory_s
        self.unknown_wait_s = unknown_wait_s
        self.last_scans: Dict[str, Tuple[np.ndarray, object]] = {}
        """Each sensor's last returns (N x 2, base_link) with the pose they were taken at."""
        self._memo: Tuple = (None, None)

    @property
    def cell_spread_m(self) -> float:
        """How much nearer (m) than a remembered cell's one hit point the rest of the obstacle
        in that cell may stand: half a cell diagonal (the part of a surface that the sensor saw
        from elsewhere, or hardly at all, before it left the view)."""
        return self.world.resolution_m / math.sqrt(2.0)

    def obstacles_base(self, pose, exclude_xy: Optional[Sequence[float]] = None,
                       exclude_radius_m: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
        """(points N x 2 in base_link at ``pose``, clearance m each) of what the robot must
        keep away from: each sensor's last scan (``robot_radius`` + ``safety_margin``) and the
        remembered obstacles within :data:`MEMORY_RADIUS_M` (where each was hit, the clearance
        grown by :attr:`cell_spread_m`), without those near ``exclude_xy`` (odom). A
        remembered obstacle out of the sensor's view stays until a scan sees its place free;
        one that scans have had in their blind zone for ``memory_s`` is dropped (there no ray
        can clear a phantom, which would otherwise block the robot for ever)."""
        if pose is None:
            return np.zeros((0, 2)), np.zeros(0)
        clearance_m = self.robot_radius_m + self.safety_margin_m
        cells = self.world.obstacle_points((pose.x, pose.y), MEMORY_RADIUS_M, self.memory_s)
        points, clearances = [cells], [np.full(len(cells), clearance_m + self.cell_spread_m)]
        for scan_points, scan in self.last_scans.values():
            points.append(avoidance.from_frame(scan_points, scan.x, scan.y, scan.yaw))
            clearances.append(np.full(len(scan_points), clearance_m))
        odom_points, clearance = np.concatenate(points), np.concatenate(clearances)
        if exclude_xy is not None:
            keep = avoidance.far_from(odom_points, exclude_xy, exclude_radius_m)
            odom_points, clearance = odom_points[keep], clearance[keep]
        return avoidance.to_frame(odom_points, pose.x, pose.y, pose.yaw), clearance

    def unknown_base(self, pose, exclude_xy: Optional[Sequence[float]] = None,
                     exclude_radius_m: float = 0.0) -> Tuple[np.ndarray, float]:
        """(points N x 2 in base_link at ``pose``, clearance m) of the unknown floor within
        :data:`MEMORY_RADIUS_M` (see :meth:`WorldMap.unknown_points`), without those near
        ``exclude_xy`` (odom): an obstacle may stand anywhere in a fine cell, so the robot
        keeps ``robot_radius`` plus half its diagonal from its centre."""
        if pose is None:
            return np.zeros((0, 2)), 0.0
        points = self.world.unknown_points((pose.x, pose.y), MEMORY_RADIUS_M,
                                           self.unknown_wait_s, self.memory_s)
        if exclude_xy is not None:
            points = points[avoidance.far_from(points, exclude_xy, exclude_radius_m)]
        return (avoidance.to_frame(points, pose.x, pose.y, pose.yaw),
                self.robot_radius_m + self.world.observed_resolution_m / math.sqrt(2.0))

    def free_travel_m(self, pose, command: Tuple[float, float], exclude_xy=None,
                      exclude_radius_m: float = 0.0, unknown: bool = True) -> float:
        """Free travel along the command's arc (m, up to the safety horizon), short of the
        obstacles and, unless ``unknown`` is false, of the unknown floor."""
        if unknown:
            return self.safety_block(pose, command, exclude_xy, exclude_radius_m)[0]
        points, clearance = self.obstacles_base(pose, exclude_xy, exclude_radius_m)
        return avoidance.free_travel_m(points, command[0], command[1], clearance,
                                       SAFETY_HORIZON_M)

    def safety_block(self, pose, command: Tuple[float, float], exclude_xy=None,
                     exclude_radius_m: float = 0.0) -> Tuple[float, Optional[np.ndarray]]:
        """(free travel m along the command's arc, short of obstacles and unknown floor; the
        unknown floor point in base_link that ends it, None when an obstacle or nothing does),
        in one pass."""
        points, clearance, obstacles = self._keep_off(pose, exclude_xy, exclude_radius_m)
        travel_m, index = avoidance.first_block(points, command[0], command[1], clearance,
                                                SAFETY_HORIZON_M)
        if index is None or index < obstacles:
            return travel_m, None
        return travel_m, points[index].copy()

    def free_travel_toward_m(self, pose, targets_base: np.ndarray, exclude_xy=None,
                             exclude_radius_m: float = 0.0) -> np.ndarray:
        """Free travel (m, up to the safety horizon) on the straight line from base_link toward
        each of ``targets_base`` (N x 2, base_link), as the safety layer counts it once the
        robot has turned in place to face that target (turning is never limited): short of
        the obstacles and of the unknown floor."""
        targets = np.asarray(targets_base, float).reshape(-1, 2)
        points, clearance, _ = self._keep_off(pose, exclude_xy, exclude_radius_m)
        return avoidance.straight_free_travel_m(points, np.arctan2(targets[:, 1], targets[:, 0]),
                                                clearance, SAFETY_HORIZON_M)

    def _keep_off(self, pose, exclude_xy, exclude_radius_m: float) -> Tuple[np.ndarray,
                                                                             np.ndarray, int]:
        """(points N x 2 in base_link, clearance m each, how many of them are obstacles) that
        the safety layer keeps the robot from: the obstacles first, then the unknown floor.
        The last answer is kept while the pose, the map and the exclusion stay the same (the
        checks of one tick ask several times)."""
        key = (pose, self.world.changes, None if exclude_xy is None
               else tuple(float(v) for v in exclude_xy), exclude_radius_m)
        if self._memo[0] != key:
            points, clearance = self.obstacles_base(pose, exclude_xy, exclude_radius_m)
            unknown_points, unknown_clearance = self.unknown_base(pose, exclude_xy,
                                                                  exclude_radius_m)
            self._memo = key, (np.concatenate((points, unknown_points)),
                               np.concatenate((clearance, np.full(len(unknown_points),
                                                                  unknown_clearance))),
                               len(points))
        return self._memo[1]
