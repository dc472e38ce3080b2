"""The can tracker on its own: which red object is the can, where it is in odom, and its gap and
bearing as the robot moves and while the camera cannot range it."""
import math
from types import SimpleNamespace

import pytest

from can_seeker.control.can_tracker import CanTracker
from can_seeker.control.controller import PARAMS
from can_seeker.control.tuning import controller_settings
from can_seeker.control.navigation import CameraView, Pose2D
from can_seeker.control.sighting import Sighting
from can_seeker.params import defaults

CONFIG = controller_settings(defaults(PARAMS))
REACH_M = CONFIG.robot_radius + CONFIG.can_radius


def tracker_at(pose=Pose2D(0.0, 0.0, 0.0), stamp_s=0.0):
    navigator = SimpleNamespace(pose=pose)
    tracker = CanTracker(CONFIG, navigator)
    tracker.observe_pose(pose, stamp_s)
    return tracker, navigator


def test_a_ranged_sighting_places_the_can_in_odom_from_the_pose_at_the_images_stamp():
    tracker, navigator = tracker_at(Pose2D(1.0, 2.0, math.pi / 2.0))
    assert tracker.observe(Sighting(0.5, 0.0), 0.0, tracking=False)
    assert tracker.can_xy == pytest.approx((1.0, 2.0 + 0.5 + REACH_M))
    navigator.pose = Pose2D(1.0, 2.2, math.pi / 2.0)        # the robot drove 0.2 m on
    tracker.observe_pose(navigator.pose, 0.1)
    assert tracker.sighting.gap_m == pytest.approx(0.3)
    assert tracker.errors()[0] == pytest.approx(0.3 - CONFIG.stop_distance)


def test_a_sighting_without_range_only_tells_the_side():
    tracker, _ = tracker_at()
    assert not tracker.observe(Sighting(math.nan, -0.2), 0.0, tracking=False)
    assert tracker.can_xy is None and tracker.turn_sign == -1.0


def test_a_weak_detection_is_the_can_only_near_it_while_tracking():
    tracker, _ = tracker_at()
    tracker.observe(Sighting(1.0, 0.0, 0.9), 0.0, tracking=False)
    weak = CONFIG.track_confidence + 0.05
    assert not tracker.observe(Sighting(1.05, 0.0, weak), 0.1, tracking=False)
    assert tracker.sighting is None
    assert tracker.observe(Sighting(1.05, 0.0, weak), 0.2, tracking=True)
    assert not tracker.observe(Sighting(1.0 + 2.0 * CONFIG.track_gate, 0.0, weak), 0.3,
                               tracking=True)


def test_carry_goes_on_with_where_the_can_was_ranged_last():
    tracker, navigator = tracker_at()
    tracker.observe(Sighting(0.6, 0.0), 0.0, tracking=False)
    tracker.observe(None, 0.1, tracking=True)
    assert tracker.sighting is None
    navigator.pose = Pose2D(0.1, 0.0, 0.0)
    tracker.carry()
    assert tracker.sighting.gap_m == pytest.approx(0.5) and tracker.sighting.confidence == 0.0


def test_below_view_once_the_cans_base_is_nearer_than_the_bottom_row():
    view = CameraView(0.12, 0.0, 0.0, math.radians(29.0), 0.12, 2.5, 0.44)
    tracker, _ = tracker_at()
    assert not tracker.below_view(view)                      # no can yet
    tracker.observe(Sighting(1.0, 0.0), 0.0, tracking=False)
    assert not tracker.below_view(view)
    tracker.observe(Sighting(CONFIG.stop_distance, 0.0), 0.1, tracking=True)
    assert tracker.below_view(view)
    assert not tracker.below_view(None)
