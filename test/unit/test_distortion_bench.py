"""The camera scan through the simulator's barrel lens (k1 -0.25, k2 0.06): with camera_info's
D honoured the ranges to a wall across the whole image width are within 3 % of the truth; with K
alone (the pinhole geometry of a raw image) they are not."""
import pathlib

import numpy as np

from can_seeker.evaluation.distortion_bench import VIEWS, wall_views

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')
K1, K2 = -0.25, 0.06


def test_with_d_the_wall_is_ranged_within_three_percent_across_the_image():
    for view in wall_views(URDF, K1, K2, honour_distortion=True):
        assert view.measured_bins >= 0.95 * view.judged_bins, view
        assert view.percentile(100) <= 0.03, (view.distance_m, view.heading_deg,
                                              view.percentile(100))


def test_with_k_alone_the_image_sides_are_ranged_wrong():
    views = wall_views(URDF, K1, K2, honour_distortion=False, views=VIEWS[-2:])
    assert max(view.percentile(100) for view in views) > 0.05
    assert np.median([view.percentile(95) for view in views]) > 0.03


def test_the_simulated_lens_distorts_as_camera_info_says_and_sees_past_the_pinhole_view():
    """Each image pixel samples the render where plumb_bob (K, D) puts it, to 0.02 px, and a
    barrel lens samples a render wide enough: no black frame in the image."""
    import cv2

    from can_seeker.camera_mount import CameraMount
    from can_seeker.sim.realism import CameraModel, RealismSpec, distortion_maps
    from can_seeker.sim.world import CameraSpec, World
    camera = CameraSpec(320, 240, 45.0, CameraMount(0.25, 25.0))
    intrinsics = camera.intrinsics
    map_x, map_y = distortion_maps(intrinsics, K1, K2)
    ideal = np.stack(((map_x.ravel() - intrinsics.cx) / intrinsics.fx,
                      (map_y.ravel() - intrinsics.cy) / intrinsics.fy,
                      np.ones(map_x.size)), axis=1)
    pixels, _ = cv2.projectPoints(ideal, np.zeros(3), np.zeros(3),
                                  np.array(intrinsics.K).reshape(3, 3),
                                  np.array([K1, K2, 0.0, 0.0, 0.0]))
    columns, rows = np.meshgrid(np.arange(320.0), np.arange(240.0))
    assert np.abs(pixels.reshape(-1, 2) - np.stack((columns.ravel(), rows.ravel()), 1)).max() \
        < 0.02
    lens = CameraModel(RealismSpec(camera_k1=K1, camera_k2=K2), intrinsics)
    assert lens.render_margin_px > 0
    assert CameraModel(RealismSpec(camera_k1=0.1), intrinsics).render_margin_px == 0
    with World(URDF, camera, renderer='tiny') as world:
        image = lens.apply(world.render('bgr8', None, lens.render_margin_px))
    assert image.shape == (240, 320, 3)
    assert image.max(axis=2).min() > 0
