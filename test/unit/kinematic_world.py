"""A tiny kinematic world for testing the controller's behaviour without a simulator: a
unicycle robot, walls and round obstacles, a ray-cast range scan (all around like a lidar, or
only what the camera sees, like obstacle_scan) and an ideal can detector that sees the can inside
the camera's field of view when nothing stands in between."""
import math
from dataclasses import dataclass, field
from typing import List, Tuple

import numpy as np

from can_seeker.control.sighting import Sighting
from can_seeker.control.navigation import CameraView, Pose2D

ROBOT_RADIUS = 0.165
CAN_RADIUS = 0.033
CAMERA_X = 0.12
CAMERA_BOTTOM_M = 0.23
"""Floor distance (m) from the camera of the image's bottom row (0.25 m high, 25 deg down, 45 deg
vertical field of view): nearer obstacles are reported there, as obstacle_scan does."""


@dataclass
class World:
    """Axis-aligned room ``[-half, half]^2`` with round obstacles (x, y, r) and a can (x, y)."""

    half_m: float
    obstacles: List[Tuple[float, float, float]]
    can_xy: Tuple[float, float] = None
    pose: Pose2D = field(default_factory=lambda: Pose2D(0.0, 0.0, 0.0))

    def ray(self, origin, angle, max_range):
        """Distance along a ray to the first wall or obstacle (inf beyond max_range)."""
        ox, oy = origin
        dx, dy = math.cos(angle), math.sin(angle)
        best = math.inf
        for wall, d in ((self.half_m - ox, dx), (-self.half_m - ox, dx),
                        (self.half_m - oy, dy), (-self.half_m - oy, dy)):
            if d != 0.0 and wall / d > 0.0:
                best = min(best, wall / d)
        for cx, cy, r in self.obstacles:
            fx, fy = ox - cx, oy - cy
            b = fx * dx + fy * dy
            c = fx * fx + fy * fy - r * r
            disc = b * b - c
            if disc >= 0.0:
                t = -b - math.sqrt(disc)
                if t > 0.0:
                    best = min(best, t)
        return best if best <= max_range else math.inf

    def scan(self, count=181, fov_rad=2 * math.pi, max_range=4.0):
        """(ends, hits) in base_link of a scan from base_link."""
        pose = self.pose
        angles = np.linspace(-fov_rad / 2, fov_rad / 2, count)
        ranges = np.array([self.ray((pose.x, pose.y), pose.yaw + a, max_range) for a in angles])
        hits = np.isfinite(ranges)
        lengths = np.where(hits, ranges, max_range)
        ends = np.stack((lengths * np.cos(angles), lengths * np.sin(angles)), axis=-1)
        return ends, hits

    def camera_scan(self, view, columns=160, max_range=4.0):
        """(ends, hits in base_link, range_min) of a camera obstacle scan: one ray per image
        column from the camera over its horizontal field of view; an obstacle nearer than the
        bottom row is reported at the bottom row; ranges from base_link."""
        pose = self.pose
        camera = (pose.x + view.x * math.cos(pose.yaw), pose.y + view.x * math.sin(pose.yaw))
        angles = np.linspace(-view.half_fov_rad, view.half_fov_rad, columns)
        ranges = np.array([self.ray(camera, pose.yaw + a, max_range) for a in angles])
        hits = np.isfinite(ranges)
        lengths = np.maximum(np.where(hits, ranges, max_range), CAMERA_BOTTOM_M)
        ends = np.stack((view.x + lengths * np.cos(angles), lengths * np.sin(angles)), axis=-1)
        return ends, hits, view.x + CAMERA_BOTTOM_M

    def clearance(self):
        """Smallest gap between the robot's circle and any wall or obstacle (m)."""
        pose = self.pose
        gaps = [self.half_m - abs(pose.x), self.half_m - abs(pose.y)]
        gaps += [math.hypot(pose.x - x, pose.y - y) - r for x, y, r in self.obstacles]
        if self.can_xy is not None:
            gaps.append(math.hypot(pose.x - self.can_xy[0], pose.y - self.can_xy[1]) - CAN_RADIUS)
        return min(gaps) - ROBOT_RADIUS

    def sighting(self, view: CameraView):
        """What an ideal detector reports, or None."""
        if self.can_xy is None:
            return None
        pose = self.pose
        cam = (pose.x + CAMERA_X * math.cos(pose.yaw), pose.y + CAMERA_X * math.sin(pose.yaw))
        dx, dy = self.can_xy[0] - cam[0], self.can_xy[1] - cam[1]
        distance = math.hypot(dx, dy)
        bearing = math.atan2(math.sin(math.atan2(dy, dx) - pose.yaw),
                             math.cos(math.atan2(dy, dx) - pose.yaw))
        if abs(bearing) > view.half_fov_rad or distance > view.far_m:
            return None
        if self.ray(cam, pose.yaw + bearing, distance) < distance - CAN_RADIUS:
            return None
        cx = self.can_xy[0] - pose.x
        cy = self.can_xy[1] - pose.y
        base = (math.cos(pose.yaw) * cx + math.sin(pose.yaw) * cy,
                -math.sin(pose.yaw) * cx + math.cos(pose.yaw) * cy)
        return Sighting(math.hypot(*base) - CAN_RADIUS - ROBOT_RADIUS, math.atan2(base[1], base[0]))

    def drive(self, command, dt):
        """Unicycle motion for one step."""
        linear, angular = command
        pose = self.pose
        yaw = pose.yaw + angular * dt / 2.0
        self.pose = Pose2D(pose.x + linear * dt * math.cos(yaw), pose.y + linear * dt * math.sin(yaw),
                           pose.yaw + angular * dt)


CAMERA_VIEW = CameraView(CAMERA_X, 0.0, 0.0, math.radians(29.0), 0.12, 2.5, CAMERA_BOTTOM_M)


def run(controller, world, duration_s, rate=20.0, scan_fov=2 * math.pi, stop_when=None,
        camera_scan=False, start_s=0.0):
    """Run the closed loop from ``start_s`` (to go on with a run that stopped), scanning all
    around within ``scan_fov`` or, with ``camera_scan``, what the camera sees; return (time
    at the end, poses, states, min clearance)."""
    controller.set_camera_view(CAMERA_VIEW)
    dt = 1.0 / rate
    now = start_s
    poses, states = [], []
    min_clearance = math.inf
    while now < start_s + duration_s:
        controller.observe_pose(world.pose, now)
        if camera_scan:
            ends, hits, range_min = world.camera_scan(CAMERA_VIEW)
        else:
            (ends, hits), range_min = world.scan(fov_rad=scan_fov), 0.0
        controller.observe_scan(controller.scan_sources[0], ends, hits, (0.0, 0.0), now, range_min)
        controller.observe_camera_info(now)
        controller.observe(world.sighting(CAMERA_VIEW), now)
        command = controller.command(now)
        world.drive(command, dt)
        min_clearance = min(min_clearance, world.clearance())
        poses.append(world.pose)
        states.append(controller.state)
        now += dt
        if stop_when is not None and stop_when(controller):
            break
    return now, poses, states, min_clearance
