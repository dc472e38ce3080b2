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
