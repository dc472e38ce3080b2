"""Camera pose, pixel rays, floor-ray and width ranges, bearing, checked against an
independent projection of a 12 oz can rasterised at pixel centres."""
import math

import cv2
import numpy as np
import pytest

from can_seeker.camera_geometry import (bearing_rad, camera_pose_from_mount,
                                        camera_pose_from_transform, can_range_bearing, floor_point,
                                        intrinsics_from_k, intrinsics_from_vertical_fov,
                                        pixel_ray, quaternion_matrix)
from can_seeker.camera_mount import CAMERA_FORWARD_M, CameraMount

CAN_RADIUS_M = 0.033
CAN_HEIGHT_M = 0.122
CAMERA_HEIGHT_M = 0.25
PITCH_RAD = math.radians(25.0)


def project(points, height_m, pitch_rad, intrinsics):
    """Image points (u, v) of points given relative to the camera's foot on the floor
    (x forward, y left, z up), for a camera ``height_m`` up, pitched down ``pitch_rad``."""
    dx, dy, dz = points[:, 0], points[:, 1], points[:, 2] - height_m
    x_opt = -dy
    y_opt = -(dx * math.sin(pitch_rad) + dz * math.cos(pitch_rad))
    z_opt = dx * math.cos(pitch_rad) - dz * math.sin(pitch_rad)
    return np.stack((intrinsics.fx * x_opt / z_opt + intrinsics.cx,
                     intrinsics.fy * y_opt / z_opt + intrinsics.cy), axis=1)


def can_mask(centre_xy, intrinsics, height_m=CAMERA_HEIGHT_M, pitch_rad=PITCH_RAD):
    """Binary mask of the can's silhouette (pixels whose centre is inside), camera at the origin."""
    angles = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    ring = np.stack((centre_xy[0] + CAN_RADIUS_M * np.cos(angles),
                     centre_xy[1] + CAN_RADIUS_M * np.sin(angles)), axis=1)
    points = np.vstack([np.column_stack((ring, np.full(len(ring), z)))
                        for z in (0.0, CAN_HEIGHT_M)])
    hull = cv2.convexHull(project(points, height_m, pitch_rad, intrinsics).astype(np.float32))
    columns, rows = np.meshgrid(np.arange(intrinsics.width), np.arange(intrinsics.height))
    polygon = hull.reshape(-1, 2).astype(np.float64)
    inside = np.ones(columns.shape, bool)
    for start, end in zip(polygon, np.roll(polygon, -1, axis=0)):
        cross = (end[0] - start[0]) * (rows - start[1]) - (end[1] - start[1]) * (columns - start[0])
        inside &= cross >= 0 if cv2.contourArea(hull.astype(np.float32), True) > 0 else cross <= 0
    return inside.astype(np.uint8)


def blob_of(mask):
    moments = cv2.moments(mask, binaryImage=True)
    x, y, width, height = cv2.boundingRect(mask)
    return (moments['m10'] / moments['m00'], moments['m01'] / moments['m00']), (x, y, width, height)


def true_range(centre_xy):
    return math.hypot(*centre_xy) - CAN_RADIUS_M


@pytest.fixture(scope='module')
def camera():
    return camera_pose_from_mount(CameraMount(CAMERA_HEIGHT_M, 25.0)), \
        intrinsics_from_vertical_fov(320, 240, 45.0)


@pytest.mark.parametrize('centre_xy', [(0.28, 0.0), (0.40, 0.05), (0.533, -0.08), (0.35, 0.12)])
def test_floor_range_is_millimetre_accurate_near(camera, centre_xy):
    pose, intrinsics = camera
    centroid, bbox = blob_of(can_mask(centre_xy, intrinsics))
    distance, bearing, method = can_range_bearing(pose, intrinsics, centroid, bbox,
                                                  2 * CAN_RADIUS_M)
    assert method == 'floor'
    assert distance == pytest.approx(true_range(centre_xy), abs=0.003)
    assert bearing == pytest.approx(math.atan2(centre_xy[1], centre_xy[0]), abs=0.02)


@pytest.mark.parametrize('centre_xy', [(1.0, 0.1), (2.0, -0.3), (3.0, 0.2)])
def test_floor_range_is_within_two_percent_far(camera, centre_xy):
    pose, intrinsics = camera
    centroid, bbox = blob_of(can_mask(centre_xy, intrinsics))
    distance, bearing, method = can_range_bearing(pose, intrinsics, centroid, bbox,
                                                  2 * CAN_RADIUS_M)
    assert method == 'floor'
    assert distance == pytest.approx(true_range(centre_xy), rel=0.02)
    assert bearing == pytest.approx(math.atan2(centre_xy[1], centre_xy[0]), abs=0.01)


def test_width_fallback_when_the_bottom_is_cut(camera):
    pose, intrinsics = camera
    centre_xy = (0.20, 0.0)
    centroid, bbox = blob_of(can_mask(centre_xy, intrinsics))
    assert bbox[1] + bbox[3] == intrinsics.height
    distance, _, method = can_range_bearing(pose, intrinsics, centroid, bbox, 2 * CAN_RADIUS_M)
    assert method == 'width'
    assert distance == pytest.approx(true_range(centre_xy), abs=0.01)


def test_no_range_when_cut_at_the_bottom_and_a_side(camera):
    pose, intrinsics = camera
    centroid, bbox = blob_of(can_mask((0.2, 0.12), intrinsics))
    assert bbox[0] == 0 or bbox[0] + bbox[2] == intrinsics.width
    distance, bearing, method = can_range_bearing(pose, intrinsics, centroid, bbox, 0.066)
    assert method == 'none' and math.isnan(distance)
    assert bearing > 0.0


def test_unknown_geometry_gives_nan():
    intrinsics = intrinsics_from_vertical_fov(320, 240, 45.0)
    pose = camera_pose_from_mount(CameraMount(0.25, 25.0))
    for args in ((None, intrinsics), (pose, None)):
        distance, bearing, method = can_range_bearing(*args, (160, 200), (150, 180, 20, 30), 0.066)
        assert math.isnan(distance) and math.isnan(bearing) and method == 'none'


def test_range_adapts_to_camera_height_and_pitch():
    intrinsics = intrinsics_from_vertical_fov(640, 480, 45.0)
    for height_m, pitch_deg in ((0.15, 10.0), (0.40, 35.0)):
        pose = camera_pose_from_mount(CameraMount(height_m, pitch_deg))
        centre_xy = (0.9, -0.1)
        centroid, bbox = blob_of(can_mask(centre_xy, intrinsics, height_m, math.radians(pitch_deg)))
        distance, _, method = can_range_bearing(pose, intrinsics, centroid, bbox, 0.066)
        assert method == 'floor'
        assert distance == pytest.approx(true_range(centre_xy), abs=0.006)


def test_row_above_the_horizon_has_no_floor_point(camera):
    pose, intrinsics = camera
    assert floor_point(pose, intrinsics, 160, 0) is not None
    level = camera_pose_from_mount(CameraMount(0.25, 0.0))
    assert floor_point(level, intrinsics, 160, 100) is None
    assert floor_point(level, intrinsics, 160, 119.5) is None


def test_principal_point_ray_hits_the_floor_where_the_pitch_says(camera):
    pose, intrinsics = camera
    x_m, y_m = floor_point(pose, intrinsics, intrinsics.cx, intrinsics.cy)
    assert x_m == pytest.approx(CAMERA_FORWARD_M + CAMERA_HEIGHT_M / math.tan(PITCH_RAD))
    assert y_m == pytest.approx(0.0, abs=1e-12)


def test_bearing_is_left_positive(camera):
    pose, intrinsics = camera
    assert bearing_rad(pose, intrinsics, intrinsics.cx, 150) == pytest.approx(0.0, abs=1e-12)
    assert bearing_rad(pose, intrinsics, 10, 150) > 0.0
    assert bearing_rad(pose, intrinsics, 310, 150) < 0.0


def test_pixel_ray_through_principal_point_is_the_optical_axis():
    intrinsics = intrinsics_from_vertical_fov(320, 240, 45.0)
    assert pixel_ray(intrinsics, intrinsics.cx, intrinsics.cy) == pytest.approx([0.0, 0.0, 1.0])
    one_focal_right = pixel_ray(intrinsics, intrinsics.cx + intrinsics.fx, intrinsics.cy)
    assert one_focal_right[0] == pytest.approx(1.0)


def test_standard_optical_quaternion_is_the_optical_rotation():
    optical_axes_in_body = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    assert quaternion_matrix(-0.5, 0.5, -0.5, 0.5) == pytest.approx(optical_axes_in_body)
    with pytest.raises(ValueError):
        quaternion_matrix(0.0, 0.0, 0.0, 0.0)


def test_mount_pose_looks_forward_and_down():
    pose = camera_pose_from_mount(CameraMount(0.25, 25.0))
    assert pose.position == pytest.approx((CAMERA_FORWARD_M, 0.0, 0.25))
    pitch = math.radians(25.0)
    assert pose.rotation[:, 2] == pytest.approx([math.cos(pitch), 0.0, -math.sin(pitch)])
    assert pose.rotation[:, 0] == pytest.approx([0.0, -1.0, 0.0])
    assert pose.heading_rad == pytest.approx(0.0, abs=1e-12)


def test_pose_from_transform_keeps_translation_and_rotation():
    pose = camera_pose_from_transform((0.1, 0.2, 0.3), (0.0, 0.0, math.sin(0.25), math.cos(0.25)))
    assert pose.position == (0.1, 0.2, 0.3)
    assert pose.rotation[:, 0] == pytest.approx([math.cos(0.5), math.sin(0.5), 0.0])


def test_intrinsics_from_k():
    intrinsics = intrinsics_from_k(320, 240, [289.7, 0, 159.5, 0, 289.7, 119.5, 0, 0, 1])
    assert (intrinsics.fx, intrinsics.cy, intrinsics.width) == (289.7, 119.5, 320)
    with pytest.raises(ValueError):
        intrinsics_from_k(320, 240, [0.0] * 9)
    with pytest.raises(ValueError):
        intrinsics_from_k(320, 240, [float('nan'), 0, 1, 0, 1, 1, 0, 0, 1])


def test_vertical_fov_intrinsics_are_unchanged():
    intrinsics = intrinsics_from_vertical_fov(320, 240, 45.0)
    assert intrinsics.fx == pytest.approx(289.706, abs=1e-3)
    assert (intrinsics.cx, intrinsics.cy) == (159.5, 119.5)


@pytest.mark.parametrize('height_m, pitch_deg, centre_xy', [
    (0.34, 25.0, (0.33, 0.06)), (0.34, 15.0, (0.38, -0.05)), (0.34, 15.0, (0.45, 0.0)),
    (0.25, 15.0, (0.33, 0.06)), (0.25, 15.0, (0.30, 0.0))])
def test_width_range_from_the_outline_is_exact_where_a_pitched_camera_leans_the_sides(
        height_m, pitch_deg, centre_xy):
    """A high camera pitched little sees the can's base leave the image before the stop
    distance. Its silhouette's sides lean toward the nadir, the box around it is 2-4 px wider
    than the silhouette at any one row: the width range from the box read 8-25 mm near; from
    the contour's pixels it is within 4 mm."""
    from can_seeker.vision.detector import red_blobs
    from can_seeker.vision.report import CanModel, can_report
    intrinsics = intrinsics_from_vertical_fov(320, 240, 45.0)
    pose = camera_pose_from_mount(CameraMount(height_m, pitch_deg))
    mask = can_mask(centre_xy, intrinsics, height_m, math.radians(pitch_deg)) * 255
    report = can_report(red_blobs(mask, 10.0), 320, 240, pose, intrinsics,
                        CanModel(2 * CAN_RADIUS_M, CAN_HEIGHT_M))
    assert report.range_method == 'width'
    assert report.range_m == pytest.approx(true_range(centre_xy), abs=0.004)
