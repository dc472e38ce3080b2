"""The image_converter's parameters and per-frame report (blobs + camera geometry -> the most
can-like blob, its range, bearing and confidence)."""
import dataclasses
import math

import pytest

from can_seeker.camera_geometry import (camera_pose_from_mount, can_image_box,
                                        intrinsics_from_vertical_fov)
from can_seeker.camera_mount import CameraMount
from can_seeker.vision.report import (PARAMS, CanModel, can_report, can_side_measures,
                                     geometry_score)
from can_seeker.vision.detector import DETECTOR_PARAMS, Blob

INTRINSICS = intrinsics_from_vertical_fov(320, 240, 45.0)
CAN = CanModel()
POSE = camera_pose_from_mount(CameraMount(0.25, 25.0))
# A can blob around the image centre, bottom at row 139, clear of every image edge.
BLOB = Blob(159.5, 120.0, 300.0, x=150, y=100, width=20, height=40)


def test_parameters_are_unique_and_valid():
    names = [spec.name for spec in PARAMS]
    assert len(names) == len(set(names))
    assert PARAMS[:len(DETECTOR_PARAMS)] == DETECTOR_PARAMS
    for spec in PARAMS:
        assert spec.coerce(spec.default) == spec.default
        assert spec.doc


def test_generated_reconfigure_defaults_and_limits_come_from_the_declarations():
    config = pytest.importorskip('can_seeker.cfg.ImageConverterConfig')
    generated = {entry['name']: entry for entry in config.config_description['parameters']}
    assert set(generated) == {spec.name for spec in DETECTOR_PARAMS}
    for spec in DETECTOR_PARAMS:
        assert generated[spec.name]['default'] == spec.default
        if spec.minimum is not None:
            assert generated[spec.name]['min'] == spec.minimum
            assert generated[spec.name]['max'] == spec.maximum


def test_not_found_report_has_nan_geometry():
    report = can_report((), 320, 240, POSE, INTRINSICS, CAN)
    assert not report.found
    assert (report.centroid_x, report.area, report.bbox) == (0.0, 0.0, (0, 0, 0, 0))
    assert (report.image_width, report.image_height) == (320, 240)
    assert math.isnan(report.range_m) and math.isnan(report.bearing_rad)


def test_found_report_uses_the_floor_ray():
    report = can_report([BLOB], 320, 240, POSE, INTRINSICS, CAN)
    assert report.found and report.range_method == 'floor'
    assert report.bbox == (150, 100, 20, 40)
    # Bottom edge at row 139.5, 20 px below the centre row: the ray 25 + 3.94 deg down meets
    # the can where its colour begins, CAN.colour_bottom_m above the floor.
    forward_m = ((0.25 - CAN.colour_bottom_m)
                 / math.tan(math.radians(25.0) + math.atan(20.0 / INTRINSICS.fy)))
    assert report.range_m == pytest.approx(forward_m, abs=1e-6)
    assert report.bearing_rad == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize('pose, intrinsics', [(None, INTRINSICS),
                                              (POSE, None)])
def test_found_report_without_geometry_keeps_the_pixels(pose, intrinsics):
    report = can_report([BLOB], 320, 240, pose, intrinsics, CAN)
    assert report.found and report.centroid_x == 159.5 and report.area == 300.0
    assert math.isnan(report.range_m) and report.range_method == 'none'

    assert report.confidence == 1.0


def test_not_found_has_zero_confidence():
    report = can_report((), 320, 240, None, None, CAN)
    assert report.confidence == 0.0 and report.chosen is None and report.confidences == ()


def can_blob_at(range_m, scale=1.0, pose=None, shape_score=1.0):
    """The blob a can at ``range_m`` straight ahead would make, its box scaled by ``scale``."""
    pose = pose or POSE
    width_px, height_px = can_image_box(pose, INTRINSICS, range_m, 0.0, 0.066, 0.122)
    # The near bottom row of a can at that range, found by the floor ray.
    bottom = min(range(11, 240), key=lambda row: abs(can_report(
        [Blob(159.5, row - 5.0, 100.0, 150, row - 10, 20, 10)], 320, 240, pose, INTRINSICS,
        CAN).range_m - range_m))
    width, height = round(width_px * scale), round(height_px * scale)
    return Blob(159.5, bottom - height / 2.0, 0.8 * width * height, round(159.5 - width / 2.0),
                bottom - height, width, height, shape_score=shape_score)


@pytest.mark.parametrize('range_m', [0.4, 1.0, 2.5])
def test_a_blob_of_a_cans_size_at_its_range_is_confident(range_m):
    report = can_report([can_blob_at(range_m)], 320, 240, POSE,
                        INTRINSICS, CAN)
    assert report.range_m == pytest.approx(range_m, rel=0.05)
    assert report.confidence == 1.0


@pytest.mark.parametrize('scale, confidence', [(1.2, 1.0), (1.45, 0.5), (1.7, 0.0),
                                               (0.55, 0.5), (0.3, 0.0)])
def test_a_blob_too_big_or_too_small_for_its_range_is_not(scale, confidence):
    blob = can_blob_at(1.0, scale)
    pose = POSE
    report = can_report([blob], 320, 240, pose, INTRINSICS, CAN)
    assert report.found
    assert report.confidence == pytest.approx(confidence, abs=0.12)


def test_size_is_not_checked_without_geometry_or_on_cut_sides():
    big = can_blob_at(1.0, 2.0)
    assert can_report([big], 320, 240, None, INTRINSICS, CAN).confidence == 1.0
    cut = dataclasses.replace(big, cut=('left', 'top'))
    pose = POSE
    assert geometry_score(cut, pose, INTRINSICS, 1.0, 0.0, 'floor', CAN) == 1.0
    assert geometry_score(big, pose, INTRINSICS, 1.0, 0.0, 'width', CAN) == 1.0
    assert geometry_score(big, pose, INTRINSICS, 1.0, 0.0, 'floor', CAN) == 0.0


def test_the_most_can_like_blob_is_reported_not_the_largest():
    can = can_blob_at(1.0)
    poster = dataclasses.replace(can_blob_at(1.0, 1.0, shape_score=0.05), area=20 * can.area,
                                 centroid_x=40.0, x=10, width=60)
    report = can_report([poster, can], 320, 240, POSE, INTRINSICS, CAN)
    assert report.chosen == 1 and report.centroid_x == can.centroid_x
    assert report.confidences[0] < 0.1 and report.confidence == 1.0


def test_equally_can_like_blobs_report_the_larger():
    small = can_blob_at(1.0, shape_score=0.8)
    large = dataclasses.replace(small, area=3 * small.area, centroid_x=60.0)
    report = can_report([large, small], 320, 240, None, None, CAN)
    assert report.chosen == 0 and report.confidence == pytest.approx(0.8)


def test_the_red_side_of_a_can_seen_from_above_has_the_lid_cut_from_its_top():
    """Seen level at mid-height the red side is the whole silhouette: convex, filling its box
    but for the rims' curves. Seen from above and close, the lid's ellipse cuts into its top:
    neither convex nor filling its box; farther away the lid flattens and both come back."""
    level = can_side_measures(camera_pose_from_mount(CameraMount(0.061, 0.0)), INTRINSICS, 0.5,
                              0.0, CAN)
    assert level[0] > 0.97 and level[1] > 0.85
    steep = camera_pose_from_mount(CameraMount(0.33, 34.6))
    near = can_side_measures(steep, INTRINSICS, 0.3, 0.0, CAN)
    far = can_side_measures(steep, INTRINSICS, 1.0, 0.0, CAN)
    assert near[0] < 0.9 and near[1] < 0.8
    assert far[0] > near[0] + 0.05 and far[1] > near[1] + 0.05
