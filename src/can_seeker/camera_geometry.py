"""Pinhole camera geometry shared by the simulator (to publish camera_info) and the detector.

Conventions: image pixels (u right, v down, pixel centres at integers), optical frame z
forward, x right, y down (REP-103); the floor frame (e.g. base_link) has z up and the floor at
z = 0. The detector turns a blob into the range and bearing of an upright can with these.
"""
import math
from dataclasses import dataclass

import numpy as np

from can_seeker.camera_mount import OPTICAL_IN_CAMERA_LINK_XYZW, CameraMount


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics without distortion (px)."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @property
    def K(self):
        """Row-major 3x3 camera matrix, as in sensor_msgs/CameraInfo."""
        return [self.fx, 0.0, self.cx, 0.0, self.fy, self.cy, 0.0, 0.0, 1.0]

    @property
    def P(self):
        """Row-major 3x4 projection matrix of a monocular camera, as in sensor_msgs/CameraInfo."""
        return [self.fx, 0.0, self.cx, 0.0, 0.0, self.fy, self.cy, 0.0, 0.0, 0.0, 1.0, 0.0]


def intrinsics_from_vertical_fov(width: int, height: int, fov_deg: float) -> CameraIntrinsics:
    """Intrinsics of an OpenGL projection with vertical field of view ``fov_deg``.

    Square pixels: fy = (H/2) / tan(fov/2) and fx = fy; the principal point is the image
    centre in pixel-centre coordinates, ((W-1)/2, (H-1)/2).
    """
    focal_px = (height / 2.0) / math.tan(math.radians(fov_deg) / 2.0)
    return CameraIntrinsics(width, height, focal_px, focal_px, (width - 1) / 2.0, (height - 1) / 2.0)


def intrinsics_from_k(width: int, height: int, k) -> CameraIntrinsics:
    """Intrinsics from a row-major 3x3 camera matrix (sensor_msgs/CameraInfo.K).

    Raises ValueError when the focal lengths are not positive and finite.
    """
    fx, cx, fy, cy = float(k[0]), float(k[2]), float(k[4]), float(k[5])
    if not (math.isfinite(fx) and math.isfinite(fy) and fx > 0.0 and fy > 0.0
            and math.isfinite(cx) and math.isfinite(cy)):
        raise ValueError('camera matrix K has no valid focal lengths: %s' % (list(k),))
    return CameraIntrinsics(int(width), int(height), fx, fy, cx, cy)


def pixel_ray(intrinsics: CameraIntrinsics, u: float, v: float) -> np.ndarray:
    """Direction (optical frame, z = 1) of the ray through image point (u, v) (px)."""
    return np.array(((u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy, 1.0))


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """Heading about z (rad) of an orientation quaternion."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quaternion_matrix(x: float, y: float, z: float, w: float) -> np.ndarray:
    """3x3 rotation matrix of a unit quaternion (normalised here)."""
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm == 0.0 or not math.isfinite(norm):
        raise ValueError('invalid quaternion (%r, %r, %r, %r)' % (x, y, z, w))
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return np.array((
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y))))


@dataclass(frozen=True)
class CameraPose:
    """The optical frame's pose in a floor frame (REP-103, z up, floor at z = 0).

    ``position`` (m) is the optical centre, ``rotation`` maps optical-frame directions into the
    floor frame (p_floor = rotation @ p_optical + position), as tf2's base <- optical transform.
    """

    position: tuple
    rotation: np.ndarray

    @property
    def height_m(self) -> float:
        return float(self.position[2])

    def to_floor_frame(self, direction_optical: np.ndarray) -> np.ndarray:
        return self.rotation @ direction_optical

    @property
    def heading_rad(self) -> float:
        """Azimuth of the optical axis projected on the floor (rad, left positive)."""
        axis = self.rotation[:, 2]
        return math.atan2(axis[1], axis[0])


def camera_pose_from_mount(mount: CameraMount) -> CameraPose:
    """Pose of camera_optical_frame in base_link (on the floor) for a camera mount."""
    optical_in_link = quaternion_matrix(*OPTICAL_IN_CAMERA_LINK_XYZW)
    rotation = quaternion_matrix(*mount.rotation_xyzw) @ optical_in_link
    return CameraPose(tuple(float(value) for value in mount.translation_m), rotation)


def camera_pose_from_transform(translation, quaternion_xyzw) -> CameraPose:
    """Pose from a floor-frame <- optical-frame transform (tf2 lookup_transform(floor, optical))."""
    return CameraPose(tuple(float(value) for value in translation),
                      quaternion_matrix(*quaternion_xyzw))


def _wrap_angle(angle_rad: float) -> float:
    return math.atan2(math.sin(angle_rad), math.cos(angle_rad))


def bearing_rad(pose: CameraPose, intrinsics: CameraIntrinsics, u: float, v: float) -> float:
    """Horizontal angle of the ray through (u, v) from the optical axis projected on the floor
    (rad, REP-103: left positive). NaN when the ray is vertical."""
    direction = pose.to_floor_frame(pixel_ray(intrinsics, u, v))
    if direction[0] == 0.0 and direction[1] == 0.0:
        return math.nan
    return _wrap_angle(math.atan2(direction[1], direction[0]) - pose.heading_rad)


def floor_point(pose: CameraPose, intrinsics: CameraIntrinsics, u: float, v: float):
    """(x, y) where the ray through (u, v) meets the floor (m, floor frame), or None when the
    ray does not point down to the floor."""
    direction = pose.to_floor_frame(pixel_ray(intrinsics, u, v))
    if direction[2] >= 0.0 or pose.height_m <= 0.0:
        return None
    scale = -pose.height_m / direction[2]
    return pose.position[0] + scale * direction[0], pose.position[1] + scale * direction[1]


def range_from_floor(pose: CameraPose, intrinsics: CameraIntrinsics, u: float, v_bottom: float,
                     bearing: float, radius_m: float) -> float:
    """Horizontal distance (m) from the camera to the near surface of an upright cylinder of
    radius ``radius_m``, from the image row ``v_bottom`` (px, lower edge) of its base.

    Without camera roll a floor point's image row depends only on its distance along the
    camera's heading, so the base's lowest row marks the heading distance of its nearest
    point, centre - radius, wherever the can is across the image. NaN when the row is at or
    above the horizon.
    """
    point = floor_point(pose, intrinsics, u, v_bottom)
    if point is None:
        return math.nan
    heading = pose.heading_rad
    forward_m = ((point[0] - pose.position[0]) * math.cos(heading)
                 + (point[1] - pose.position[1]) * math.sin(heading))
    centre_m = (forward_m + radius_m) / math.cos(bearing)
    return centre_m - radius_m


def range_from_width(pose: CameraPose, intrinsics: CameraIntrinsics, u_left: float,
                     u_right: float, v: float, radius_m: float) -> float:
    """Horizontal distance (m) from the camera to the near surface of an upright cylinder of
    radius ``radius_m`` whose silhouette spans columns ``u_left``..``u_right`` (px, outer edges).

    The silhouette's sides are vertical lines where vertical planes through the camera touch
    the cylinder, so their azimuths are exact at any row: half the angle between them is
    asin(radius / distance to the axis).
    """
    left = pose.to_floor_frame(pixel_ray(intrinsics, u_left, v))
    right = pose.to_floor_frame(pixel_ray(intrinsics, u_right, v))
    half_angle = abs(_wrap_angle(math.atan2(left[1], left[0]) - math.atan2(right[1], right[0]))) / 2
    if half_angle <= 0.0 or half_angle >= math.pi / 2:
        return math.nan
    return radius_m / math.sin(half_angle) - radius_m


OUTLINE_EDGE_PX = 0.0
"""Where the outline's extreme pixels put the silhouette's side, beyond their centres (px).
A side that leans across columns (a pitched camera leans every side off the image's centre
column) has, among its pixels, one whose centre lies just inside the edge: the extreme centre
is the edge (a vertical side would read up to a pixel narrow)."""


def range_from_outline(pose: CameraPose, intrinsics: CameraIntrinsics, outline_px,
                       radius_m: float) -> float:
    """Horizontal distance (m) from the camera to the near surface of an upright cylinder of
    radius ``radius_m`` whose silhouette's pixels include ``outline_px`` (N x 2 (u, v), e.g.
    the blob's contour: pixel centres).

    Every point of the cylinder lies between the azimuths of its two silhouette sides, and
    each side, a vertical line, has one azimuth along its whole length: the extreme azimuths
    of the outline's pixel edges are the sides' wherever along them the image shows a piece.
    A pitched camera leans vertical lines toward its nadir, so the box around the silhouette
    pairs each side's outermost column with a row where that side is not (the width at one
    row over-reads the angle, by more the steeper the view: 2-3 px close up from a high
    camera, the can ranged 10-25 mm near at 0.3 m); azimuths of the pixels themselves do not.
    """
    points = np.asarray(outline_px, float).reshape(-1, 2)
    if len(points) == 0:
        return math.nan
    u = np.concatenate((points[:, 0] - OUTLINE_EDGE_PX, points[:, 0] + OUTLINE_EDGE_PX))
    v = np.concatenate((points[:, 1], points[:, 1]))
    rays = np.stack(((u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy,
                     np.ones_like(u)))
    floor = pose.rotation @ rays
    azimuth = np.arctan2(floor[1], floor[0]) - pose.heading_rad
    azimuth = np.arctan2(np.sin(azimuth), np.cos(azimuth))
    half_angle = float(azimuth.max() - azimuth.min()) / 2.0
    if half_angle <= 0.0 or half_angle >= math.pi / 2:
        return math.nan
    return radius_m / math.sin(half_angle) - radius_m


def can_range_bearing(pose, intrinsics, centroid, bbox, diameter_m: float, outline_px=None):
    """(range_m, bearing_rad, method) of an upright can seen as a blob.

    ``centroid`` is (u, v) (px); ``bbox`` is (x, y, width, height) of the blob (px, inclusive
    of x and y); ``outline_px`` its contour's pixels (N x 2 (u, v), optional: for the width
    range, which otherwise takes the box's sides at the centroid's row). ``method`` is 'floor'
    (ray through the blob's bottom), 'width' (the bottom is cut by the image edge, so the
    apparent width is used), or 'none' (NaN range: geometry unknown, or the blob is cut at the
    bottom and a side). Range and bearing are NaN when ``pose`` or ``intrinsics`` is None.
    """
    if pose is None or intrinsics is None:
        return math.nan, math.nan, 'none'
    u, v = centroid
    x, y, width, height = bbox
    radius_m = diameter_m / 2.0
    bearing = bearing_rad(pose, intrinsics, u, v)
    if y + height < intrinsics.height:
        distance = range_from_floor(pose, intrinsics, u, y + height - 0.5, bearing, radius_m)
        if math.isfinite(distance):
            return distance, bearing, 'floor'
    if x > 0 and x + width < intrinsics.width:
        if outline_px is not None and len(outline_px):
            distance = range_from_outline(pose, intrinsics, outline_px, radius_m)
        else:
            distance = range_from_width(pose, intrinsics, x - 0.5, x + width - 0.5, v, radius_m)
        if math.isfinite(distance):
            return distance, bearing, 'width'
    return math.nan, bearing, 'none'


def project_floor_points(pose: CameraPose, intrinsics: CameraIntrinsics, points_m: np.ndarray):
    """Image points (u, v) (px) of floor-frame points (N x 3, m); rows behind the camera are
    dropped."""
    optical = (np.asarray(points_m, float) - np.asarray(pose.position)) @ pose.rotation
    optical = optical[optical[:, 2] > 1e-6]
    u = intrinsics.fx * optical[:, 0] / optical[:, 2] + intrinsics.cx
    v = intrinsics.fy * optical[:, 1] / optical[:, 2] + intrinsics.cy
    return np.stack((u, v), axis=1)


def can_rims_px(pose: CameraPose, intrinsics: CameraIntrinsics, range_m: float,
                bearing: float, diameter_m: float, height_m: float, samples: int = 24):
    """(bottom rim, top rim): image points (samples x 2, px) of the rims of an upright can seen
    at ``range_m`` (to its near surface) and ``bearing`` (rad) from the camera. None when the
    can is not entirely in front of the camera."""
    radius_m = diameter_m / 2.0
    heading = pose.heading_rad + bearing
    centre_x = pose.position[0] + (range_m + radius_m) * math.cos(heading)
    centre_y = pose.position[1] + (range_m + radius_m) * math.sin(heading)
    angles = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    rim = np.stack((centre_x + radius_m * np.cos(angles), centre_y + radius_m * np.sin(angles),
                    np.zeros(samples)), axis=1)
    points = np.concatenate((rim, rim + (0.0, 0.0, height_m)))
    pixels = project_floor_points(pose, intrinsics, points)
    if len(pixels) < len(points):
        return None
    return pixels[:samples], pixels[samples:]


def can_image_box(pose: CameraPose, intrinsics: CameraIntrinsics, range_m: float,
                  bearing: float, diameter_m: float, height_m: float, samples: int = 24):
    """(width, height) in px of the box around an upright can seen at ``range_m`` (to its near
    surface) and ``bearing`` (rad) from the camera: its top and bottom rims projected. None
    when the can is not entirely in front of the camera."""
    rims = can_rims_px(pose, intrinsics, range_m, bearing, diameter_m, height_m, samples)
    if rims is None:
        return None
    pixels = np.concatenate(rims)
    extent = pixels.max(axis=0) - pixels.min(axis=0)
    return float(extent[0]), float(extent[1])
