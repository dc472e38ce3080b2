"""The image_converter's parameters and per-frame report (blob + camera geometry)."""
import math

import pytest

from can_seeker.camera_geometry import intrinsics_from_vertical_fov
from can_seeker.vision.report import PARAMS, can_report, fallback_pose
from can_seeker.vision.detector import DETECTOR_PARAMS, Blob

INTRINSICS = intrinsics_from_vertical_fov(320, 240, 45.0)
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


def test_zero_camera_height_means_unknown():
    assert fallback_pose(0.0, 25.0) is None
    pose = fallback_pose(0.3, 20.0)
    assert pose.height_m == pytest.approx(0.3)


def test_not_found_report_has_nan_geometry():
    report = can_report(None, 320, 240, fallback_pose(0.25, 25.0), INTRINSICS, 0.066)
    assert not report.found
    assert (report.centroid_x, report.area, report.bbox) == (0.0, 0.0, (0, 0, 0, 0))
    assert (report.image_width, report.image_height) == (320, 240)
    assert math.isnan(report.range_m) and math.isnan(report.bearing_rad)


def test_found_report_uses_the_floor_ray():
    report = can_report(BLOB, 320, 240, fallback_pose(0.25, 25.0), INTRINSICS, 0.066)
    assert report.found and report.range_method == 'floor'
    assert report.bbox == (150, 100, 20, 40)
    # Bottom edge at row 139.5, 20 px below the centre row: the floor ray is 25 + 3.94 deg down.
    forward_m = 0.25 / math.tan(math.radians(25.0) + math.atan(20.0 / INTRINSICS.fy))
    assert report.range_m == pytest.approx(forward_m, abs=1e-6)
    assert report.bearing_rad == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize('pose, intrinsics', [(None, INTRINSICS),
                                              (fallback_pose(0.25, 25.0), None)])
def test_found_report_without_geometry_keeps_the_pixels(pose, intrinsics):
    report = can_report(BLOB, 320, 240, pose, intrinsics, 0.066)
    assert report.found and report.centroid_x == 159.5 and report.area == 300.0
    assert math.isnan(report.range_m) and report.range_method == 'none'
