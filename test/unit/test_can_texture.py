"""The textured soda can: its label image, its mesh, and how it renders."""
import pathlib

import numpy as np
import pytest

from can_seeker.camera_mount import CameraMount
from can_seeker.can_size import CAN_COLOUR_BOTTOM_M
from can_seeker.sim.can_texture import (BASE_FRACTION, LETTERING_BOTTOM_FRACTION,
                                        LETTERING_TOP_FRACTION, LID_FRACTION, SILVER_RGB,
                                        label_image, mesh_obj)
from can_seeker.sim.scene import CAN_HEIGHT_M, CAN_RADIUS_M
from can_seeker.sim.world import CameraSpec, World

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')
RED = (204, 13, 13)


def test_label_has_silver_rims_a_lettering_band_and_a_red_body():
    label = label_image(RED, 512, 256).astype(int)
    assert label.shape == (256, 512, 3)
    assert np.all(label[1, :] >= 150) and np.all(np.abs(label[-1, :] - SILVER_RGB) <= 1)
    assert int(LID_FRACTION * 256) > 10 and int(BASE_FRACTION * 256) >= 10
    band = label[int(LETTERING_TOP_FRACTION * 256):int(LETTERING_BOTTOM_FRACTION * 256)]
    white = np.all(band > 200, axis=2)
    assert 0.1 < white.mean() < 0.5
    red_columns = np.all(band == RED, axis=2).all(axis=0)
    assert red_columns.mean() > 0.2, 'letters need body colour between them'
    body = label[int(0.7 * 256):int(0.9 * 256)]
    assert np.all(body == RED)


@pytest.mark.parametrize('height_px', [256, 100])
def test_the_silver_base_ends_where_the_vision_takes_the_cans_colour_to_begin(height_px):
    """The label's unprinted base, on the simulated can's height, is CAN_COLOUR_BOTTOM_M tall
    within one label row: the floor ray through the red's lower edge meets the can there."""
    label = label_image(RED, 64, height_px)
    silver_rows = np.all(label == SILVER_RGB, axis=(1, 2))[::-1]
    base_rows = int(np.argmin(silver_rows))
    assert base_rows > 0 and np.all(label[-base_rows - 1] == RED)
    row_m = CAN_HEIGHT_M / height_px
    assert abs(base_rows * row_m - CAN_COLOUR_BOTTOM_M) <= row_m


def test_the_mesh_base_maps_to_the_silver_base():
    label = label_image(RED)
    text = mesh_obj(CAN_RADIUS_M, CAN_HEIGHT_M)
    base_v = [float(line.split()[2]) for line in text.splitlines()
              if line.startswith('vt 0.5 ')][0]
    row = int((1.0 - base_v) * label.shape[0])
    assert np.all(label[row] == SILVER_RGB)


def test_mesh_is_a_closed_cylinder_of_the_can():
    text = mesh_obj(0.033, 0.122, segments=16)
    vertices = np.array([[float(v) for v in line.split()[1:]]
                         for line in text.splitlines() if line.startswith('v ')])
    faces = [line for line in text.splitlines() if line.startswith('f ')]
    assert len(faces) == 4 * 16
    radii = np.hypot(vertices[:, 0], vertices[:, 1])
    assert radii.max() == pytest.approx(0.033, abs=1e-5)
    assert vertices[:, 2].min() == pytest.approx(-0.061)
    assert vertices[:, 2].max() == pytest.approx(0.061)
    coordinates = [tuple(map(float, line.split()[1:])) for line in text.splitlines()
                   if line.startswith('vt ')]
    assert all(0.0 <= u <= 1.0 and 0.0 <= v <= 1.0 for u, v in coordinates)


def test_the_textured_can_renders_red_white_and_silver():
    camera = CameraSpec(160, 120, 45.0, CameraMount(0.25, 25.0))
    with World(URDF, camera, renderer='tiny', can_texture='textured') as world:
        world.place_can(0.5, 0.0)
        world.step()
        bgr = world.render('bgr8').astype(int)
        blue, green, red = bgr[:, :, 0], bgr[:, :, 1], bgr[:, :, 2]
        reddish = (red > 60) & (red > 2 * green) & (red > 2 * blue)
        greyish = (np.abs(red - blue) < 20) & (np.abs(red - green) < 20) & (red > 120)
        rows, columns = np.nonzero(reddish)
        assert rows.size > 100
        can_box = greyish[rows.min() - 8:rows.max() + 4, columns.min():columns.max() + 1]
        assert can_box.sum() > 20
        world.set_can_color((0.05, 0.7, 0.05, 1.0))
        world.step()
        bgr = world.render('bgr8').astype(int)
        assert not ((bgr[:, :, 2] > 60) & (bgr[:, :, 2] > 2 * bgr[:, :, 1])).any()


def test_an_unknown_texture_is_refused():
    with pytest.raises(ValueError, match='can_texture'):
        World(URDF, CameraSpec(32, 24, 45.0, CameraMount(0.25, 25.0)), renderer='tiny',
              can_texture='chrome')


def range_errors(texture):
    """Relative range errors of the detector's floor-ray range to the can's near surface at
    0.3-3 m and three bearings, rendered with TinyRenderer (None where the can was missed)."""
    from can_seeker.vision.detector import RedCanDetector
    from can_seeker.camera_geometry import camera_pose_from_mount
    from can_seeker.vision.report import CanModel, can_report
    camera = CameraSpec(320, 240, 45.0, CameraMount(0.25, 25.0))
    pose, detector = camera_pose_from_mount(camera.mount), RedCanDetector()
    errors = []
    with World(URDF, camera, renderer='tiny', can_texture=texture) as world:
        for range_m in (0.3, 0.5, 0.8, 1.2, 1.8, 2.4, 3.0):
            for bearing in (-0.2, 0.0, 0.2):
                centre_m = range_m + 0.033
                world.place_can(0.12 + centre_m * np.cos(bearing), centre_m * np.sin(bearing))
                world.step()
                result = detector.detect(world.render('bgr8'))
                report = can_report(result.candidates, 320, 240, pose, camera.intrinsics,
                                    CanModel())
                errors.append((report.range_m - range_m) / range_m if report.found else None)
    return errors


def test_the_detector_finds_and_ranges_the_textured_can_like_the_plain_one():
    """Found at 0.3-3 m; the textured can's red begins above its silver base (5 mm, which
    CAN_COLOUR_BOTTOM_M accounts for), so compared with the plain can, red to the floor, its
    range reads longer by 1-3 % with the camera 0.25 m up, and within a pixel row (up to 4 % at
    3 m) of that beyond 0.8 m."""
    plain, textured = range_errors('plain'), range_errors('textured')
    assert None not in plain and None not in textured
    bias = np.subtract(textured, plain).reshape(7, 3)
    assert np.all((bias[:3] > 0.01) & (bias[:3] < 0.03)), np.round(bias, 3)
    assert np.all((bias[3:] > -0.005) & (bias[3:] < 0.045)), np.round(bias, 3)


def reports_straight_ahead(height_m, pitch_deg, fov_deg, ranges_m):
    """(range, image_converter's report) of the textured can straight ahead at each of
    ``ranges_m`` (to its near surface from the camera), rendered with TinyRenderer at 320x240
    from a camera ``height_m`` up pitched ``pitch_deg`` down."""
    from can_seeker.vision.detector import RedCanDetector
    from can_seeker.camera_geometry import camera_pose_from_mount
    from can_seeker.vision.report import CanModel, can_report
    camera = CameraSpec(320, 240, fov_deg, CameraMount(height_m, pitch_deg))
    pose, detector = camera_pose_from_mount(camera.mount), RedCanDetector()
    with World(URDF, camera, renderer='tiny', can_texture='textured') as world:
        for range_m in ranges_m:
            world.place_can(0.12 + range_m + 0.033, 0.0)
            world.step()
            yield range_m, can_report(detector.detect(world.render('bgr8')).candidates, 320,
                                      240, pose, camera.intrinsics, CanModel())


@pytest.mark.parametrize('height_m, pitch_deg, fov_deg', [(0.102, 0.0, 48.8), (0.25, 25.0, 45.0)])
def test_the_textured_cans_range_at_the_stop_is_true_from_a_low_level_camera_too(
        height_m, pitch_deg, fov_deg):
    """At 0.3-0.5 m (where the controller stops) the range is within 1.5 % of the truth, from
    a level camera 0.1 m up (a TurtleBot3 Waffle Pi's) as from one 0.25 m up pitched 25 deg:
    the floor ray through the red's lower edge meets the can 5 mm up, not on the floor, which
    read 5-6 % long from the low camera."""
    for range_m, report in reports_straight_ahead(height_m, pitch_deg, fov_deg, (0.3, 0.4, 0.5)):
        assert report.range_m == pytest.approx(range_m, rel=0.015), (range_m, report.range_m)


def test_a_steep_camera_is_sure_of_the_can_close_below_it():
    """A camera 0.33 m up pitched 35 deg down sees the can 0.25-0.4 m away from above: the
    lid cuts into the red side's top and the lettering notches its sides (solidity 0.85-0.92).
    Judged as a silhouette seen from the side that scores 0.37 at 0.25 m, below the
    controller's MIN_CONFIDENCE, so the controller would lose the can at its stop point;
    judged against the red side of a can seen from there, it is sure of it."""
    for range_m, report in reports_straight_ahead(0.33, 34.6, 45.0, (0.25, 0.3, 0.4)):
        assert report.confidence > 0.8, (range_m, report.confidence)
        assert report.range_m == pytest.approx(range_m, rel=0.05)
