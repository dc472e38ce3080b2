"""Pinhole camera geometry shared by the simulator (to publish camera_info) and the detector.

Conventions: image pixels (u right, v down, pixel centres at integers), optical frame z
forward, x right, y down (REP-103); the floor frame (e.g. base_link) has z up and the floor at
z = 0. The detector turns a blob into the range and bearing of an upright can with these.

Lens distortion: a raw image (camera_info ``D`` non-zero) bends every ray; the geometry undoes
it on the pixel coordinates it uses (cv2.undistortPoints with K and D), never on whole images.
A rectified image (``D`` all zero, or ``~image_rectified``) is a pinhole image of ``P``
(:func:`intrinsics_from_camera_info`).
"""
import math
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.camera_mount import OPTICAL_IN_CAMERA_LINK_XYZW, CameraMount
from can_seeker.params import Param

DISTORTION_MODELS = {'plumb_bob': (4, 5), 'rational_polynomial': (8,)}
"""camera_info distortion models the geometry undoes, with the lengths D may have in each."""
UNDISTORT_CRITERIA = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-10)
"""Iterations of cv2.undistortPointsIter: its default 5 leave 0.2 px in the corners of a
60 deg barrel lens; these converge to 1e-10 (normalised) in a few more."""

CAMERA_INFO_PARAMS = (
    Param('image_rectified', False, 'the images are rectified (image_proc\'s image_rect): use '
          'camera_info\'s P and ignore D; false: undo D (plumb_bob, rational_polynomial) on '
          'the pixels the geometry uses, or use P when D is all zero'),
)
"""How an image node reads camera_info."""


@dataclass(frozen=True)
class CameraIntrinsics:
    """Camera matrix of the image's pixels (px) and the lens distortion to undo first:
    ``distortion`` is camera_info's D for it (OpenCV order, k1 k2 p1 p2 [k3 [k4 k5 k6]]);
    empty for a pinhole (undistorted or rectified) image."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    distortion: Tuple[float, ...] = ()

    @property
    def camera_matrix(self) -> np.ndarray:
        return np.array(((self.fx, 0.0, self.cx), (0.0, self.fy, self.cy), (0.0, 0.0, 1.0)))

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


def intrinsics_from_camera_info(width: int, height: int, k, d, p, distortion_model: str,
                                rectified: bool = False) -> CameraIntrinsics:
    """The intrinsics the image's pixels have, from sensor_msgs/CameraInfo's fields.

    A raw image (``d`` has a non-zero coefficient and not ``rectified``) keeps K and D: its
    pixels are undistorted before any ray. Otherwise the image is a pinhole image of P (the
    rectified camera: D is none of its business), or of K when P holds no focal lengths (a
    driver that leaves P zero). Raises ValueError for a matrix without valid focal lengths, or
    a distortion this module does not undo (then rectify the images with image_proc and set
    ``~image_rectified``).
    """
    coefficients = tuple(float(value) for value in d)
    if not rectified and any(value != 0.0 for value in coefficients):
        lengths = DISTORTION_MODELS.get(distortion_model)
        if lengths is None:
            raise ValueError('distortion model %r is not undone here (plumb_bob, '
                             'rational_polynomial are): rectify the images (image_proc) and '
                             'set ~image_rectified' % distortion_model)
        if len(coefficients) not in lengths or not all(map(math.isfinite, coefficients)):
            raise ValueError('%s distortion D needs %s finite coefficients, got %s' % (
                distortion_model, ' or '.join(map(str, lengths)), list(coefficients)))
        intrinsics = intrinsics_from_k(width, height, k)
        return CameraIntrinsics(intrinsics.width, intrinsics.height, intrinsics.fx,
                                intrinsics.fy, intrinsics.cx, intrinsics.cy, coefficients)
    p = [float(value) for value in p]
    if len(p) == 12 and p[0] > 0.0 and p[5] > 0.0:
        return intrinsics_from_k(width, height, (p[0], p[1], p[2], p[4], p[5], p[6], 0, 0, 1))
    return intrinsics_from_k(width, height, k)


def normalized_points(intrinsics: CameraIntrinsics, u, v) -> Tuple[np.ndarray, np.ndarray]:
    """(x, y) on the optical frame's z = 1 plane of the rays through image points (u, v) (px,
    arrays of one shape): the lens distortion undone when the intrinsics have one."""
    u, v = np.asarray(u, np.float64), np.asarray(v, np.float64)
    if not intrinsics.distortion:
        return (u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy
    points = np.stack((u.ravel(), v.ravel()), axis=-1).reshape(-1, 1, 2)
    ideal = cv2.undistortPointsIter(points, intrinsics.camera_matrix,
                                    np.asarray(intrinsics.distortion), None, None,
                                    UNDISTORT_CRITERIA).reshape(-1, 2)
    return ideal[:, 0].reshape(u.shape), ideal[:, 1].reshape(u.shape)


def image_points(intrinsics: CameraIntrinsics, optical_m: np.ndarray) -> np.ndarray:
    """Image points (N x 2, px) of optical-frame points (N x 3, in front: z > 0), through the
    lens distortion when the intrinsics have one."""
    optical_m = np.asarray(optical_m, np.float64).reshape(-1, 3)
    if not intrinsics.distortion:
        return np.stack((intrinsics.fx * optical_m[:, 0] / optical_m[:, 2] + intrinsics.cx,
                         intrinsics.fy * optical_m[:, 1] / optical_m[:, 2] + intrinsics.cy),
                        axis=1)
    pixels, _ = cv2.projectPoints(optical_m, np.zeros(3), np.zeros(3),
                                  intrinsics.camera_matrix, np.asarray(intrinsics.distortion))
    return pixels.reshape(-1, 2)


def pixel_ray(intrinsics: CameraIntrinsics, u: float, v: float) -> np.ndarray:
    """Direction (optical frame, z = 1) of the ray through image point (u, v) (px)."""
    x, y = normalized_points(intrinsics, u, v)
    return np.array((float(x), float(y), 1.0))


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

    Without camera roll a floor point's row in a pinhole image (a raw image's pixel
    undistorted) depends only on its distance along the camera's heading, so the base's
    lowest row marks the heading distance of its nearest
    point, centre - radius, wherever the can is across the image. NaN when the row is at or
    above the horizon.
    """
    return _range_from_base_ray(pose, pixel_ray(intrinsics, u, v_bottom), bearing, radius_m)


def _range_from_base_ray(pose: CameraPose, ray_optical: np.ndarray, bearing: float,
                         radius_m: float, colour_bottom_m: float = 0.0) -> float:
    """:func:`range_from_floor` from the ray (optical frame) through the lower edge of the
    can's colour, ``colour_bottom_m`` above the floor (0: the colour reaches the floor)."""
    direction = pose.to_floor_frame(ray_optical)
    drop_m = pose.height_m - colour_bottom_m
    if direction[2] >= 0.0 or drop_m <= 0.0:
        return math.nan
    scale = -drop_m / direction[2]
    point = (pose.position[0] + scale * direction[0], pose.position[1] + scale * direction[1])
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
    rays = np.stack((*normalized_points(intrinsics, u, v), np.ones_like(u)))
    floor = pose.rotation @ rays
    azimuth = np.arctan2(floor[1], floor[0]) - pose.heading_rad
    azimuth = np.arctan2(np.sin(azimuth), np.cos(azimuth))
    half_angle = float(azimuth.max() - azimuth.min()) / 2.0
    if half_angle <= 0.0 or half_angle >= math.pi / 2:
        return math.nan
    return radius_m / math.sin(half_angle) - radius_m


def _base_ray(intrinsics: CameraIntrinsics, u: float, v_bottom: float,
              outline_px=None) -> np.ndarray:
    """Ray (optical frame, z = 1) through the lower edge of a blob's base: the image point
    (``u``, ``v_bottom``) in a pinhole image. Distortion bends the base's row, so in a raw
    image it is the lowest once undone of that point and the lower edges of the outline's
    pixels (N x 2 (u, v), optional)."""
    if not intrinsics.distortion or outline_px is None or not len(outline_px):
        return pixel_ray(intrinsics, u, v_bottom)
    points = np.asarray(outline_px, np.float64).reshape(-1, 2)
    x, y = normalized_points(intrinsics, np.append(points[:, 0], u),
                             np.append(points[:, 1] + 0.5, v_bottom))
    lowest = int(np.argmax(y))
    return np.array((x[lowest], y[lowest], 1.0))


def can_range_bearing(pose, intrinsics, centroid, bbox, diameter_m: float, outline_px=None,
                      colour_bottom_m: float = 0.0):
    """(range_m, bearing_rad, method) of an upright can seen as a blob.

    ``colour_bottom_m`` is how far above the floor the blob's colour begins (a soda can's
    unprinted base): the ray through the blob's lower edge meets the can there, not on the
    floor, which matters the more the lower the camera (5 mm read as floor put a can 4.5 %
    too far from a level camera 0.1 m up).

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
        distance = _range_from_base_ray(
            pose, _base_ray(intrinsics, u, y + height - 0.5, outline_px), bearing, radius_m,
            colour_bottom_m)
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
    """Image points (u, v) (px) of floor-frame points (N x 3, m), through the lens distortion
    when the intrinsics have one; rows behind the camera are dropped."""
    optical = (np.asarray(points_m, float) - np.asarray(pose.position)) @ pose.rotation
    return image_points(intrinsics, optical[optical[:, 2] > 1e-6])


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


OPTICAL_AXIS_TOLERANCE = math.cos(math.radians(45.0))
"""How far an optical frame's x axis may turn from the base's right (-y) (roll or yaw): 45 deg."""


def optical_frame_problem(pose: CameraPose, frame_id: str) -> Optional[str]:
    """Why the frame ``frame_id`` with this pose in a floor frame (z up, x forward) is no
    optical frame the geometry can use, or None when it is one: its x axis (image right) must
    point to the base's right (-y) within 45 deg, and its z axis (the optical axis) within
    90 deg of forward-and-down (from 45 deg above the horizon, through forward, to 45 deg
    past straight down). A REP-103 body frame (a camera_link: x forward, z up) fails both."""
    x_axis, z_axis = pose.rotation[:, 0], pose.rotation[:, 2]
    problems = []
    if -x_axis[1] < OPTICAL_AXIS_TOLERANCE:
        problems.append('its x axis (image right) points (%.2f, %.2f, %.2f) in the base frame, '
                        'not to the robot\'s right (-y)' % tuple(x_axis))
    if z_axis[0] - z_axis[2] <= 0.0:
        problems.append('its z axis (the optical axis) points (%.2f, %.2f, %.2f), not forward '
                        'or down' % tuple(z_axis))
    if not problems:
        return None
    return ('image frame %r is not an optical frame: %s (a camera_link is x forward, z up; '
            'or the camera is rolled more than 45 deg). Stamp images in camera_optical_frame, '
            'z forward, x right, y down (REP-103)' % (frame_id, '; '.join(problems)))
