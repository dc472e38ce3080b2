"""The camera contract: camera_info's D undone on the pixels the geometry uses (raw images),
P used for rectified ones; the image frame checked for an optical frame; the camera mount from
TF only."""
import math

import cv2
import numpy as np
import pytest
import tf2_ros
from geometry_msgs.msg import Transform

from can_seeker.camera_geometry import (camera_pose_from_mount, camera_pose_from_transform,
                                        can_range_bearing, floor_point,
                                        intrinsics_from_camera_info, optical_frame_problem,
                                        pixel_ray, quaternion_matrix)
from can_seeker.camera_mount import CameraMount
from can_seeker.control.controller import PARAMS as CAN_STOPPER_PARAMS
from can_seeker.nodes import image_converter_node, obstacle_scan_node
from can_seeker.ros.camera_pose import CameraPoseSource
from can_seeker.vision.camera_scan import scan_geometry

K = [300.0, 0.0, 161.0, 0.0, 302.0, 118.0, 0.0, 0.0, 1.0]
P = [300.0, 0.0, 161.0, 0.0, 0.0, 302.0, 118.0, 0.0, 0.0, 0.0, 1.0, 0.0]
BARREL = [-0.25, 0.06, 0.0005, -0.0004, 0.0]
MOUNT = CameraMount(0.25, 25.0)


def project(pose, points_m, d):
    """Image points (px) of floor-frame points through K and ``d`` (cv2.projectPoints)."""
    optical = (np.asarray(points_m, float) - np.asarray(pose.position)) @ pose.rotation
    pixels, _ = cv2.projectPoints(optical, np.zeros(3), np.zeros(3),
                                  np.array(K).reshape(3, 3), np.array(d, float))
    return pixels.reshape(-1, 2)


# Floor points seen near the image's corners and sides, where a barrel lens bends most.
FLOOR_POINTS = [(0.75, 0.27, 0.0), (0.60, -0.2, 0.0), (1.6, 0.55, 0.0), (0.9, 0.0, 0.0)]


@pytest.mark.parametrize('model, d', [('plumb_bob', BARREL),
                                      ('rational_polynomial',
                                       [-0.2, 0.05, 0.0003, 0.0002, 0.01, 0.02, -0.01, 0.005])])
def test_a_distorted_pixel_gives_its_floor_point_within_a_millimetre(model, d):
    pose = camera_pose_from_mount(MOUNT)
    intrinsics = intrinsics_from_camera_info(320, 240, K, d, P, model)
    for point, pixel in zip(FLOOR_POINTS, project(pose, FLOOR_POINTS, d)):
        x, y = floor_point(pose, intrinsics, *pixel)
        assert math.hypot(x - point[0], y - point[1]) < 0.001, (point, (x, y))


def test_with_k_alone_the_same_distorted_pixel_is_ranged_wrong():
    """What the geometry did before it read D (K alone): the far corner point's floor point
    off by more than 5 % of its range."""
    pose = camera_pose_from_mount(MOUNT)
    pinhole = intrinsics_from_camera_info(320, 240, K, [0.0] * 5, P, 'plumb_bob')
    point = FLOOR_POINTS[2]
    x, y = floor_point(pose, pinhole, *project(pose, [point], BARREL)[0])
    assert math.hypot(x - point[0], y - point[1]) > 0.05 * math.hypot(*point[:2])


def test_a_can_at_the_image_side_is_ranged_and_beared_through_the_lens():
    """The can's base rim, projected through the lens, gives its range within 5 mm and its
    bearing within 0.2 deg: the blob's outline is undone point by point."""
    pose = camera_pose_from_mount(MOUNT)
    intrinsics = intrinsics_from_camera_info(320, 240, K, BARREL, P, 'plumb_bob')
    centre = np.array((0.62, 0.24))
    radius = 0.033
    angles = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False)
    rim = np.stack((centre[0] + radius * np.cos(angles), centre[1] + radius * np.sin(angles),
                    np.zeros(angles.size)), axis=1)
    outline = np.concatenate((project(pose, rim, BARREL),
                              project(pose, rim + (0.0, 0.0, 0.122), BARREL)))
    bottom = outline[:, 1].max()
    x0, y0 = np.floor(outline.min(axis=0))
    box = (int(x0), int(y0), int(np.ceil(outline[:, 0].max()) - x0),
           int(math.ceil(bottom - 0.5) - y0 + 1))
    # The outline's pixel centres: the lowest lies half a pixel above the rim's edge.
    pixels = outline - (0.0, 0.5) * (outline[:, 1:2] >= bottom - 1e-9)
    centroid = project(pose, [(centre[0], centre[1], 0.061)], BARREL)[0]
    range_m, bearing, method = can_range_bearing(pose, intrinsics, centroid, box, 2 * radius,
                                                 pixels)
    camera_xy = np.array(pose.position[:2])
    assert method == 'floor'
    assert range_m == pytest.approx(np.linalg.norm(centre - camera_xy) - radius, abs=0.005)
    true_bearing = math.atan2(*(centre - camera_xy)[::-1])
    assert math.degrees(abs(bearing - true_bearing)) < 0.2


def test_rectified_images_use_p_and_ignore_d():
    p = [280.0, 0.0, 150.0, 0.0, 0.0, 281.0, 115.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    raw = intrinsics_from_camera_info(320, 240, K, BARREL, p, 'plumb_bob')
    assert (raw.fx, raw.cx, raw.distortion) == (300.0, 161.0, tuple(BARREL))
    rectified = intrinsics_from_camera_info(320, 240, K, BARREL, p, 'plumb_bob',
                                            rectified=True)
    assert (rectified.fx, rectified.fy, rectified.cx, rectified.cy) == (280.0, 281.0, 150.0,
                                                                        115.0)
    assert rectified.distortion == ()
    zero_d = intrinsics_from_camera_info(320, 240, K, [0.0] * 5, p, 'plumb_bob')
    assert zero_d == rectified
    no_p = intrinsics_from_camera_info(320, 240, K, [], [0.0] * 12, '')
    assert (no_p.fx, no_p.cx, no_p.distortion) == (300.0, 161.0, ())
    # A rectified image's ray is P's pinhole ray.
    assert pixel_ray(rectified, 150.0 + 28.0, 115.0) == pytest.approx((0.1, 0.0, 1.0))


def test_a_distortion_it_cannot_undo_is_refused_with_the_fix():
    with pytest.raises(ValueError, match='image_rectified'):
        intrinsics_from_camera_info(320, 240, K, [0.1, 0.0, 0.0, 0.0], P, 'equidistant')
    with pytest.raises(ValueError, match='coefficients'):
        intrinsics_from_camera_info(320, 240, K, [0.1, 0.0, 0.0], P, 'plumb_bob')
    assert intrinsics_from_camera_info(320, 240, K, [0.1, 0.0, 0.0, 0.0], P, 'equidistant',
                                       rectified=True).distortion == ()


def test_the_scan_geometry_undoes_the_lens_across_the_image():
    """Every bottom-row pixel's floor range in the scan tables matches its true floor point."""
    pose = camera_pose_from_mount(MOUNT)
    intrinsics = intrinsics_from_camera_info(320, 240, K, BARREL, P, 'plumb_bob')
    geometry = scan_geometry(pose, intrinsics, 4.0)
    columns = np.arange(0, 320, 16, dtype=float)
    ranges = geometry.range_m[200, columns.astype(int)]
    for column, range_m in zip(columns, ranges):
        x, y = floor_point(pose, intrinsics, column, 200.5)
        assert range_m == pytest.approx(math.hypot(x, y), abs=1e-6)
        pixel = project(pose, [(x, y, 0.0)], BARREL)[0]
        assert pixel == pytest.approx((column, 200.5), abs=1e-3)


# The optical frame check.

def optical_pose(roll_deg=0.0, mount=MOUNT):
    """The mount's optical frame, rolled about its optical axis by ``roll_deg``."""
    pose = camera_pose_from_mount(mount)
    half = math.radians(roll_deg) / 2.0
    roll = quaternion_matrix(0.0, 0.0, math.sin(half), math.cos(half))
    return camera_pose_from_transform(pose.position, _quaternion(pose.rotation @ roll))


def _quaternion(rotation):
    w = math.sqrt(max(0.0, 1.0 + np.trace(rotation))) / 2.0
    if w > 1e-6:
        return ((rotation[2, 1] - rotation[1, 2]) / (4 * w),
                (rotation[0, 2] - rotation[2, 0]) / (4 * w),
                (rotation[1, 0] - rotation[0, 1]) / (4 * w), w)
    axis = int(np.argmax(np.diag(rotation)))
    q = np.zeros(4)
    q[axis] = math.sqrt(max(0.0, 1.0 + 2 * rotation[axis, axis] - np.trace(rotation))) / 2.0
    for other in range(3):
        if other != axis:
            q[other] = (rotation[axis, other] + rotation[other, axis]) / (4 * q[axis])
    q[3] = (rotation[(axis + 2) % 3, (axis + 1) % 3]
            - rotation[(axis + 1) % 3, (axis + 2) % 3]) / (4 * q[axis])
    return tuple(q)


def camera_link_pose(mount=MOUNT):
    """camera_link (x forward, z up, pitched down), passed off as the image frame."""
    return camera_pose_from_transform(mount.translation_m, mount.rotation_xyzw)


@pytest.mark.parametrize('mount', [MOUNT, CameraMount(0.6, 80.0), CameraMount(0.2, -25.0)])
def test_an_optical_frame_passes(mount):
    assert optical_frame_problem(optical_pose(0.0, mount), 'camera_optical_frame') is None
    assert optical_frame_problem(optical_pose(15.0, mount), 'camera_optical_frame') is None


@pytest.mark.parametrize('mount', [MOUNT, CameraMount(0.6, 70.0), CameraMount(0.2, -25.0)])
def test_camera_link_as_image_frame_is_named_with_the_fix(mount):
    problem = optical_frame_problem(camera_link_pose(mount), 'robot1/camera_link')
    assert problem is not None
    assert "'robot1/camera_link'" in problem
    assert 'camera_optical_frame, z forward' in problem


def test_a_camera_rolled_past_45_degrees_is_refused_and_a_slight_roll_is_kept():
    assert optical_frame_problem(optical_pose(60.0), 'camera_optical_frame') is not None
    assert optical_frame_problem(optical_pose(-90.0), 'camera_optical_frame') is not None
    assert optical_frame_problem(optical_pose(180.0), 'camera_optical_frame') is not None
    assert optical_frame_problem(optical_pose(30.0), 'camera_optical_frame') is None


def transform_of(pose):
    transform = Transform()
    (transform.translation.x, transform.translation.y,
     transform.translation.z) = pose.position
    (transform.rotation.x, transform.rotation.y, transform.rotation.z,
     transform.rotation.w) = _quaternion(pose.rotation)
    return transform


def test_the_pose_source_gives_no_pose_for_a_wrong_frame_and_says_why():
    frames = {'camera_optical_frame': transform_of(optical_pose()),
              'camera_link': transform_of(camera_link_pose())}
    errors = []
    source = CameraPoseSource(lambda base, frame: frames[frame], 'base_link',
                              require_optical=True, error=errors.append)
    assert source.pose('camera_link', 0.0) is None
    assert errors and "'camera_link'" in errors[-1] and 'no range' in errors[-1]
    assert 'camera_link' in source.problems and not source.from_tf_yet('camera_link')
    pose = source.pose('camera_optical_frame', 0.0)
    assert pose is not None and pose.height_m == pytest.approx(0.25)
    assert 'camera_optical_frame' not in source.problems
    # A frame with no TF (yet) gets no pose either, and an error naming the transform.
    frames.pop('camera_optical_frame')
    source.clear()

    def missing(base, frame):
        raise tf2_ros.LookupException(frame)
    source.lookup = missing
    assert source.pose('camera_optical_frame', 1.0) is None
    assert errors[-1].startswith('no TF base_link <- camera_optical_frame')


def test_a_wrong_frame_gives_a_detection_without_range_or_bearing():
    """What image_converter reports for a can seen in a frame the source refused: NaN."""
    intrinsics = intrinsics_from_camera_info(320, 240, K, [], P, 'plumb_bob')
    source = CameraPoseSource(lambda base, frame: transform_of(camera_link_pose()),
                              'base_link', require_optical=True)
    range_m, bearing, method = can_range_bearing(source.pose('camera_link', 0.0), intrinsics,
                                                 (160.0, 150.0), (150, 120, 20, 40), 0.066)
    assert math.isnan(range_m) and math.isnan(bearing) and method == 'none'
    # Taken as an optical frame, the same blob would get a (wrong) range.
    wrong = can_range_bearing(camera_link_pose(), intrinsics, (160.0, 150.0),
                              (150, 120, 20, 40), 0.066)
    assert not math.isnan(wrong[1])


# The camera mount from TF only.

def test_no_node_has_camera_mount_parameters():
    """The mount is TF's (robot_description, robot_state.launch); no node parameter can
    disagree with it."""
    for params in (image_converter_node.PARAMS, obstacle_scan_node.PARAMS, CAN_STOPPER_PARAMS):
        names = [spec.name for spec in params]
        assert not {'camera_height', 'camera_pitch_deg', 'camera_x'} & set(names)
    for params in (image_converter_node.PARAMS, obstacle_scan_node.PARAMS):
        assert [spec.name for spec in params].count('image_rectified') == 1
