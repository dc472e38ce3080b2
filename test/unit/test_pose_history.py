"""Poses by stamp, and the controller measuring a late frame's can from where the robot is now."""
import math

import pytest

from can_seeker.control.supervisor import State
from can_seeker.control.navigation import Pose2D
from can_seeker.control.pose_history import PoseHistory, sighting_from
from test_control import ahead, make_controller


def test_history_interpolates_between_stamps_and_clamps_outside():
    history = PoseHistory(span_s=1.0)
    assert history.at(0.0) is None
    history.add(1.0, Pose2D(0.0, 0.0, math.radians(170.0)))
    history.add(2.0, Pose2D(1.0, 2.0, math.radians(-170.0)))
    middle = history.at(1.5)
    assert (middle.x, middle.y) == pytest.approx((0.5, 1.0))
    assert math.degrees(middle.yaw) == pytest.approx(180.0) or \
        math.degrees(middle.yaw) == pytest.approx(-180.0)
    assert history.at(0.5) == Pose2D(0.0, 0.0, math.radians(170.0))
    assert history.at(9.0) == Pose2D(1.0, 2.0, math.radians(-170.0))


def test_history_keeps_its_span_and_ignores_older_stamps():
    history = PoseHistory(span_s=1.0)
    for step in range(31):
        history.add(step * 0.1, Pose2D(step * 0.1, 0.0, 0.0))
    history.add(0.5, Pose2D(99.0, 0.0, 0.0))
    assert history.at(3.0).x == pytest.approx(3.0)
    assert history.at(0.0).x == pytest.approx(2.0)


def test_sighting_from_a_pose_is_the_gap_to_the_near_surface_and_the_centre_bearing():
    gap_m, bearing_rad = sighting_from((1.0, 1.0), Pose2D(1.0, 0.0, 0.0), 0.165, 0.033)
    assert gap_m == pytest.approx(1.0 - 0.165 - 0.033)
    assert math.degrees(bearing_rad) == pytest.approx(90.0)


def test_a_late_frame_is_measured_from_where_the_robot_is_now():
    """The frame was taken 0.2 s ago, 0.06 m further back: the gap now is 0.06 m less than the
    image shows (a controller taking the image's gap stops 6 cm too close)."""
    controller = make_controller()
    for step in range(21):
        controller.observe_pose(Pose2D(0.3 * step * 0.01, 0.0, 0.0), 10.0 + step * 0.01)
    controller.observe(ahead(0.8), 10.2, image_stamp_s=10.0)
    assert controller.state is State.APPROACH
    assert controller.sighting.gap_m == pytest.approx(0.8 - 0.06, abs=1e-9)
    assert controller.sighting.bearing_rad == pytest.approx(0.0, abs=1e-9)
    controller.observe_pose(Pose2D(0.1, 0.0, 0.0), 10.25)
    assert controller.sighting.gap_m == pytest.approx(0.8 - 0.1, abs=1e-9)
