"""The stop-near-can state machine, transition by transition, and its control law."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from can_seeker.camera_geometry import (camera_pose_from_mount, camera_pose_from_transform,
                                        intrinsics_from_vertical_fov)
from can_seeker.camera_mount import CameraMount
from can_seeker.control.navigation import CameraView, Pose2D, camera_view
from can_seeker.control.behaviours.approach import dead_band
from can_seeker.control.behaviours.base import Result
from can_seeker.control.controller import PARAMS, Controller
from can_seeker.control.tuning import controller_settings
from can_seeker.control.reasons import Kind, Then, reason
from can_seeker.control.sighting import (Sighting, camera_floor_pose,
                                         detection_problem, detection_shows_can,
                                         sighting_from_detection)
from can_seeker.control.supervisor import State
from can_seeker.health import ERROR, OK, WARN
from can_seeker.params import defaults, read_params

DEFAULTS = vars(controller_settings(defaults(PARAMS)))
STOP = DEFAULTS['stop_distance']
DT = 1.0 / DEFAULTS['rate']


def make_controller(**overrides):
    """A controller without obstacle sensing (the direct law), unless overridden."""
    return Controller(SimpleNamespace(**{**DEFAULTS, 'scan_topics': '', **overrides}))


def ahead(gap_m, bearing_deg=0.0):
    return Sighting(gap_m, math.radians(bearing_deg))


def run(controller, sighting, start_s, duration_s):
    """Feed the same sighting at the control rate; return the last command and the end time."""
    now = start_s
    command = None
    while now < start_s + duration_s - 1e-9:
        controller.observe(sighting, now)
        command = controller.command(now)
        now += DT
    return command, now


# Geometry ------------------------------------------------------------------------------------

def test_sighting_straight_ahead_gap_is_range_minus_camera_setback():
    camera = Pose2D(0.12, 0.0, 0.0)
    sighting = sighting_from_detection(True, 0.5, 0.0, camera, 0.165, 0.033)
    assert sighting.gap_m == pytest.approx(0.5 + 0.12 - 0.165)
    assert sighting.bearing_rad == pytest.approx(0.0)


def test_sighting_off_axis_uses_can_centre_seen_from_base_link():
    camera = Pose2D(0.12, 0.0, 0.0)
    bearing = math.radians(20.0)
    sighting = sighting_from_detection(True, 1.0, bearing, camera, 0.165, 0.033)
    centre = (0.12 + 1.033 * math.cos(bearing), 1.033 * math.sin(bearing))
    assert sighting.gap_m == pytest.approx(math.hypot(*centre) - 0.033 - 0.165)
    assert sighting.bearing_rad == pytest.approx(math.atan2(centre[1], centre[0]))
    assert 0.0 < sighting.bearing_rad < bearing


def test_sighting_without_range_keeps_the_side():
    sighting = sighting_from_detection(True, math.nan, -0.3, Pose2D(0.12, 0.0, 0.0),
                                       0.165, 0.033)
    assert not sighting.has_range
    assert sighting.bearing_rad == pytest.approx(-0.3)


def test_sighting_without_a_camera_pose_has_no_range_and_keeps_the_side():
    """TF has no pose of the detection's camera: its range cannot be placed in base_link."""
    sighting = sighting_from_detection(True, 1.0, -0.3, None, 0.165, 0.033, 0.9)
    assert not sighting.has_range and math.isnan(sighting.gap_m)
    assert sighting.bearing_rad == pytest.approx(-0.3) and sighting.confidence == 0.9


def test_detections_without_a_camera_pose_never_place_the_can_or_drive():
    controller = make_controller()
    sighting = sighting_from_detection(True, 1.0, math.radians(-20.0), None, 0.165, 0.033)
    now = 0.0
    for _ in range(60):
        controller.observe(sighting, now)
        linear, angular = controller.command(now)
        assert linear == 0.0 and angular <= 0.0
        now += DT
    assert controller.state is State.SEARCH and controller.can_xy is None
    assert angular == pytest.approx(-DEFAULTS['search_angular'])


@pytest.mark.parametrize('found, range_m, bearing', [
    (False, 1.0, 0.0), (True, 1.0, math.nan), (True, -0.2, 0.0), (True, math.inf, 0.0)])
def test_no_sighting_from_empty_or_malformed_detection(found, range_m, bearing):
    assert sighting_from_detection(found, range_m, bearing, Pose2D(0.12, 0.0, 0.0),
                                   0.165, 0.033) is None


def test_detection_problem_names_malformed_fields_only():
    assert detection_problem(False, math.nan, math.nan) is None
    assert detection_problem(True, math.nan, 0.1) is None
    assert 'bearing' in detection_problem(True, 1.0, math.nan)
    assert 'range' in detection_problem(True, -1.0, 0.0)


def quaternion_from_axes(x_axis, y_axis, z_axis):
    """(x, y, z, w) of the rotation whose columns are the given frame axes (trace > -1)."""
    rotation = [[x_axis[row], y_axis[row], z_axis[row]] for row in range(3)]
    qw = math.sqrt(1.0 + rotation[0][0] + rotation[1][1] + rotation[2][2]) / 2.0
    return ((rotation[2][1] - rotation[1][2]) / (4.0 * qw),
            (rotation[0][2] - rotation[2][0]) / (4.0 * qw),
            (rotation[1][0] - rotation[0][1]) / (4.0 * qw), qw)


def test_camera_pose_from_optical_frame_pitched_down():
    # camera at (0.12, 0, 0.25) pitched 25 deg down: optical x is the robot's right,
    # optical z forward and down, optical y = z cross x (down and back)
    pitch = math.radians(25.0)
    quaternion = quaternion_from_axes((0.0, -1.0, 0.0),
                                      (-math.sin(pitch), 0.0, -math.cos(pitch)),
                                      (math.cos(pitch), 0.0, -math.sin(pitch)))
    pose = camera_floor_pose(camera_pose_from_transform((0.12, 0.0, 0.25), quaternion))
    assert (pose.x, pose.y) == (0.12, 0.0)
    assert pose.yaw == pytest.approx(0.0, abs=1e-9)


def test_camera_pose_from_optical_frame_looking_left():
    quaternion = quaternion_from_axes((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0))
    pose = camera_floor_pose(camera_pose_from_transform((0.1, 0.05, 0.3), quaternion))
    assert (pose.x, pose.y) == (0.1, 0.05)
    assert pose.yaw == pytest.approx(math.pi / 2.0)


def test_dead_band():
    assert dead_band(0.004, 0.005, 1.5, 0.03) == 0.0
    assert dead_band(0.006, 0.005, 1.5, 0.03) == 0.03
    assert dead_band(-0.006, 0.005, 1.5, 0.03) == -0.03
    assert dead_band(0.2, 0.005, 1.5, 0.03) == pytest.approx(0.3)


# Transitions ---------------------------------------------------------------------------------

def test_starts_in_search_turning_left():
    controller = make_controller()
    assert controller.state is State.SEARCH
    controller.observe(None, 0.0)
    command, _ = run(controller, None, 0.0, 2.0)
    assert command[0] == 0.0
    assert command[1] == pytest.approx(DEFAULTS['search_angular'])


def test_search_turns_toward_side_seen_without_range():
    controller = make_controller()
    command, _ = run(controller, Sighting(math.nan, math.radians(-20.0)), 0.0, 2.0)
    assert controller.state is State.SEARCH
    assert command == (0.0, pytest.approx(-DEFAULTS['search_angular']))


def test_search_to_approach_on_ranged_sighting():
    controller = make_controller()
    controller.observe(ahead(1.0), 0.0)
    assert controller.state is State.APPROACH


def test_approach_drives_forward_and_steers_toward_bearing():
    controller = make_controller()
    command, _ = run(controller, ahead(1.5, 5.0), 0.0, 3.0)
    assert controller.state is State.APPROACH
    assert command[0] == pytest.approx(DEFAULTS['max_linear'] * (1 - 5.0 / 25.0))
    assert command[1] == pytest.approx(DEFAULTS['angular_gain'] * math.radians(5.0))


def test_approach_turns_in_place_when_can_is_far_off_axis():
    controller = make_controller()
    command, _ = run(controller, ahead(1.0, -40.0), 0.0, 2.0)
    assert command[0] == 0.0
    assert command[1] == pytest.approx(-DEFAULTS['max_angular'])


def test_approach_slows_down_near_target_but_keeps_minimum_speed():
    controller = make_controller()
    far, _ = run(controller, ahead(STOP + 0.5), 0.0, 3.0)
    near, _ = run(controller, ahead(STOP + 0.08), 3.0, 1.0)
    close, _ = run(controller, ahead(STOP + 0.007), 4.0, 1.0)
    assert far[0] == pytest.approx(DEFAULTS['max_linear'])
    assert near[0] == pytest.approx(min(1.5 * 0.08, math.sqrt(2 * 0.5 * 0.08)))
    assert close[0] == pytest.approx(DEFAULTS['min_linear'])


def test_approach_speed_profile_can_brake_within_remaining_gap():
    controller = make_controller(linear_gain=10.0)
    for gap_error in (0.02, 0.05, 0.1, 0.2):
        controller.tracker.sighting = ahead(STOP + gap_error)
        linear, _ = controller.parts.approach.approach_law()
        braking_distance = linear ** 2 / (2 * DEFAULTS['max_linear_accel'])
        assert braking_distance <= gap_error + 1e-12


def test_approach_backs_up_when_too_close_and_never_drives_forward():
    controller = make_controller()
    command, _ = run(controller, ahead(STOP - 0.05), 0.0, 2.0)
    assert command[0] == pytest.approx(-0.075)
    moving = make_controller()
    run(moving, ahead(1.0), 0.0, 3.0)
    moving.observe(ahead(STOP - 0.003), 3.0)
    assert moving.command(3.0 + DT)[0] == 0.0


def test_approach_to_stopped_when_within_tolerance_and_at_rest():
    controller = make_controller()
    run(controller, ahead(STOP + 0.3), 0.0, 3.0)
    assert controller.state is State.APPROACH
    command, _ = run(controller, ahead(STOP + 0.004, 0.5), 3.0, 1.0)
    assert controller.state is State.STOPPED
    assert command == (0.0, 0.0)


def test_approach_stays_while_bearing_is_outside_tolerance():
    controller = make_controller()
    command, _ = run(controller, ahead(STOP, 3.0), 0.0, 2.0)
    assert controller.state is State.APPROACH
    assert command[0] == 0.0
    assert command[1] == pytest.approx(max(DEFAULTS['min_angular'], 2.0 * math.radians(3.0)))


def test_approach_to_lost_when_can_leaves_view_and_turns_toward_where_it_left():
    controller = make_controller()
    run(controller, ahead(1.0, -10.0), 0.0, 1.0)
    controller.observe(None, 1.0)
    assert controller.state is State.LOST
    command, _ = run(controller, None, 1.0, 2.0)
    assert command[0] == 0.0
    assert command[1] == pytest.approx(-DEFAULTS['search_angular'])


def test_approach_to_lost_on_detection_without_range():
    controller = make_controller()
    controller.observe(ahead(1.0, 10.0), 0.0)
    controller.observe(Sighting(math.nan, math.radians(25.0)), 0.1)
    assert controller.state is State.LOST
    assert controller.tracker.turn_sign == 1.0


def test_lost_to_approach_when_can_is_seen_again():
    controller = make_controller()
    controller.observe(ahead(1.0), 0.0)
    controller.observe(None, 0.1)
    controller.observe(ahead(0.9), 0.2)
    assert controller.state is State.APPROACH


def test_lost_to_search_after_lost_timeout():
    controller = make_controller(lost_timeout=1.0)
    controller.observe(ahead(1.0, 5.0), 0.0)
    controller.observe(None, 0.05)
    run(controller, None, 0.05, 0.9)
    assert controller.state is State.LOST
    command, _ = run(controller, None, 0.95, 0.3)
    assert controller.state is State.SEARCH
    assert command[1] == pytest.approx(DEFAULTS['search_angular'])


def stopped_controller():
    controller = make_controller()
    run(controller, ahead(STOP + 0.002), 0.0, 1.0)
    assert controller.state is State.STOPPED
    return controller


def test_stopped_holds_inside_hysteresis():
    controller = stopped_controller()
    command, _ = run(controller, ahead(STOP + 0.04, 5.0), 1.0, 1.0)
    assert controller.state is State.STOPPED
    assert command == (0.0, 0.0)


VANISH_S = DEFAULTS['vanish_timeout']


def test_stopped_holds_while_the_can_is_missed_for_less_than_the_vanish_timeout():
    controller = stopped_controller()
    command, now = run(controller, None, 1.0, VANISH_S - 0.2)
    assert controller.state is State.STOPPED
    assert command == (0.0, 0.0)
    run(controller, ahead(STOP + 0.002), now, 0.2)
    run(controller, None, now + 0.2, VANISH_S - 0.2)
    assert controller.state is State.STOPPED


def test_stopped_to_lost_when_the_can_vanished_then_search():
    controller = stopped_controller()
    run(controller, ahead(STOP + 0.002, -1.0), 1.0, 0.2)
    command, now = run(controller, None, 1.2, VANISH_S + 0.2)
    assert controller.state is State.LOST
    assert command[0] == 0.0 and command[1] < 0.0, 'turns toward the side it was last seen'
    run(controller, None, now, DEFAULTS['lost_timeout'] + 0.2)
    assert controller.state is State.SEARCH


def test_stopped_to_lost_when_only_seen_without_range():
    controller = stopped_controller()
    run(controller, Sighting(math.nan, 0.3), 1.0, VANISH_S + 0.2)
    assert controller.state is State.LOST


def test_stopped_to_approach_when_can_moves_away():
    controller = stopped_controller()
    command, _ = run(controller, ahead(STOP + 0.3), 1.0, 1.0)
    assert controller.state is State.APPROACH
    assert command[0] > 0.0


def test_stopped_to_approach_when_can_moves_sideways():
    controller = stopped_controller()
    controller.observe(ahead(STOP, 8.0), 1.0)
    assert controller.state is State.APPROACH


def test_reset_returns_to_search_at_rest():
    controller = make_controller()
    run(controller, ahead(1.0, -5.0), 0.0, 2.0)
    controller.reset()
    assert controller.state is State.SEARCH
    assert controller.last_command == (0.0, 0.0)
    assert controller.tracker.turn_sign == 1.0


def test_reset_ignores_detections_of_images_taken_before_it():
    controller = make_controller()
    run(controller, ahead(STOP), 0.0, 2.0)
    controller.reset(10.0)
    controller.observe(ahead(STOP), 10.05, image_stamp_s=9.95)
    assert controller.state is State.SEARCH
    assert controller.command(10.05) == (0.0, 0.0)
    controller.observe(ahead(1.0), 10.1, image_stamp_s=10.02)
    assert controller.state is State.APPROACH


# Watchdog and limits -------------------------------------------------------------------------

def test_no_detection_yet_gives_zero():
    controller = make_controller()
    assert controller.command(0.0) == (0.0, 0.0)
    assert controller.command(5.0) == (0.0, 0.0)


def test_stale_detection_gives_immediate_zero_in_any_state():
    controller = make_controller()
    command, now = run(controller, ahead(1.5), 0.0, 3.0)
    assert command[0] > 0.3
    last_message = now - DT
    assert controller.command(last_message + 0.44)[0] > 0.0
    assert controller.command(last_message + 0.46) == (0.0, 0.0)
    assert controller.state is State.APPROACH


def test_commands_respect_acceleration_limit():
    controller = make_controller()
    controller.observe(ahead(2.0), 0.0)
    previous = controller.command(0.0)
    for step in range(1, 40):
        controller.observe(ahead(2.0), step * DT)
        current = controller.command(step * DT)
        assert abs(current[0] - previous[0]) <= DEFAULTS['max_linear_accel'] * DT + 1e-12
        previous = current


def test_closed_loop_point_robot_stops_within_tolerance_without_overshoot():
    """A kinematic robot driven by the controller from 2 m, can 30 deg to the left."""
    controller = make_controller()
    x, y, heading = 0.0, 0.0, 0.0
    can = (2.0 * math.cos(math.radians(30)), 2.0 * math.sin(math.radians(30)))
    min_gap = math.inf
    now = 0.0
    for _ in range(int(60.0 / DT)):
        dx, dy = can[0] - x, can[1] - y
        gap = math.hypot(dx, dy) - 0.033 - 0.165
        bearing = math.atan2(dy, dx) - heading
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        visible = abs(bearing) < math.radians(28)
        controller.observe(Sighting(gap, bearing) if visible else None, now)
        linear, angular = controller.command(now)
        x += linear * math.cos(heading) * DT
        y += linear * math.sin(heading) * DT
        heading += angular * DT
        min_gap = min(min_gap, gap)
        now += DT
        if controller.state is State.STOPPED:
            break
    assert controller.state is State.STOPPED
    assert abs(gap - STOP) <= DEFAULTS['distance_tolerance']
    assert abs(bearing) <= math.radians(DEFAULTS['bearing_tolerance_deg'])
    assert min_gap >= STOP - DEFAULTS['distance_tolerance']
    assert now < 15.0


def test_only_confident_detections_show_the_can():
    assert detection_shows_can(True, 0.8, 0.5)
    assert detection_shows_can(True, 0.5, 0.5)
    assert not detection_shows_can(True, 0.3, 0.5)
    assert not detection_shows_can(False, 1.0, 0.5)
    assert detection_shows_can(True, 0.0, 0.0)


def tracked_controller(gap_m):
    """Approaching a can seen confidently ``gap_m`` ahead, the robot at rest at the origin."""
    controller = make_controller()
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe(ahead(gap_m), 0.0)
    assert controller.state is State.APPROACH
    return controller


def test_a_weaker_detection_where_the_can_is_keeps_the_approach():
    """Hysteresis: close up a label changes the silhouette's score from frame to frame."""
    controller = tracked_controller(0.5)
    weak = DEFAULTS['track_confidence'] + 0.05
    assert weak < DEFAULTS['min_confidence']
    controller.observe(Sighting(0.48, 0.02, weak), 0.05)
    assert controller.state is State.APPROACH
    assert controller.sighting.gap_m == 0.48


def test_a_weaker_detection_elsewhere_or_too_weak_is_no_can():
    controller = tracked_controller(0.5)
    weak = DEFAULTS['track_confidence'] + 0.05
    controller.observe(Sighting(0.5 + DEFAULTS['track_gate'] + 0.1, 0.0, weak), 0.05)
    assert controller.state is State.LOST
    controller = tracked_controller(0.5)
    controller.observe(Sighting(0.5, 0.0, DEFAULTS['track_confidence'] - 0.05), 0.05)
    assert controller.state is State.LOST


def test_a_weaker_detection_does_not_start_an_approach():
    controller = make_controller()
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe(Sighting(0.5, 0.0, DEFAULTS['min_confidence'] - 0.05), 0.0)
    assert controller.state is State.SEARCH
    assert controller.sighting is None


def test_no_hysteresis_with_a_zero_gate():
    controller = Controller(SimpleNamespace(**dict(DEFAULTS, scan_topics='', track_gate=0.0)))
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe(ahead(0.5), 0.0)
    controller.observe(Sighting(0.5, 0.0, DEFAULTS['min_confidence'] - 0.05), 0.05)
    assert controller.state is State.LOST


# Robustness ----------------------------------------------------------------------------------

def read_with(name, value):
    """The controller's parameters with ``~name`` set to ``value``, and the warnings."""
    warnings = []
    values = read_params(PARAMS, lambda key, default: value if key == '~' + name else default,
                         warnings.append)
    return values, warnings


@pytest.mark.parametrize('name,bad', [
    ('max_linear', 0.005), ('max_linear', math.nan), ('max_linear', 'crawl'),
    ('max_reverse', -0.1), ('max_angular', math.inf), ('max_linear_accel', 0.01),
    ('max_angular_accel', True), ('input_timeout', 20.0), ('input_timeout', math.nan),
    ('input_timeout', 'slow'), ('robot_radius', -0.01), ('safety_margin', math.nan),
    ('stop_distance', 0.0),
])
def test_an_invalid_motion_bound_is_refused_never_replaced_by_its_default(name, bad):
    with pytest.raises(ValueError, match=name):
        read_with(name, bad)


def test_other_invalid_parameters_still_warn_and_use_the_default():
    values, warnings = read_with('wander_clearance', 10.0)
    assert values.wander_clearance == DEFAULTS['wander_clearance']
    assert len(warnings) == 1 and 'wander_clearance' in warnings[0]


def test_backing_up_stops_for_a_remembered_obstacle_behind():
    def backing_up(obstacle_behind):
        controller = make_controller(scan_topics='/scan')
        controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
        ends, hits = CLEAR_SCAN
        if obstacle_behind:
            ends, hits = np.vstack((ends, [[-0.27, 0.0]])), np.append(hits, True)
        controller.observe_scan('/scan', ends, hits, (0.0, 0.0), 0.0)
        # then a sensor that looks ahead only: the obstacle behind is remembered
        front = CLEAR_SCAN[0][:, 0] > 0.0
        now, command = 0.0, None
        for _ in range(40):
            controller.observe_pose(Pose2D(0.0, 0.0, 0.0), now)
            controller.observe_scan('/scan', CLEAR_SCAN[0][front], CLEAR_SCAN[1][front],
                                    (0.0, 0.0), now)
            controller.observe_camera_info(now)
            controller.observe(ahead(STOP - 0.1), now)
            command = controller.command(now)
            now += DT
        return command

    assert backing_up(False)[0] == pytest.approx(-DEFAULTS['max_reverse'])
    assert backing_up(True)[0] == 0.0


def test_a_failed_tick_counts_as_a_zero_command():
    controller = make_controller()
    command, now = run(controller, ahead(1.5), 0.0, 3.0)
    assert command[0] > 0.3
    controller.observe(ahead(1.5), now)
    approach = controller.supervisor.behaviours[State.APPROACH]
    approach.command = failing
    with pytest.raises(RuntimeError):
        controller.command(now)
    del approach.command
    controller.observe(ahead(1.5), now + DT)
    linear, _ = controller.command(now + DT)
    assert 0.0 <= linear <= DEFAULTS['max_linear_accel'] * DT + 1e-12


def failing(_now_s):
    raise RuntimeError('broken')


def test_a_non_finite_desired_command_is_refused_not_limited():
    controller = make_controller()
    _, now = run(controller, ahead(1.5), 0.0, 3.0)
    controller.observe(ahead(1.5), now)
    controller.supervisor.behaviours[State.APPROACH].command = lambda _now_s: Result(
        (math.nan, 0.0))
    with pytest.raises(ValueError, match='finite'):
        controller.command(now)
    assert controller.last_command == (0.0, 0.0)


def test_a_late_old_detection_is_stale():
    controller = make_controller()
    command, now = run(controller, ahead(1.5), 0.0, 3.0)
    assert command[0] > 0.3
    controller.observe(ahead(1.5), now, image_stamp_s=now - DEFAULTS['detection_timeout'] - 0.1)
    assert controller.command(now) == (0.0, 0.0)
    controller.observe(ahead(1.5), now + DT, image_stamp_s=now)
    assert controller.command(now + DT)[0] > 0.0


def test_a_detection_stamped_in_the_future_ages_from_its_arrival():
    controller = make_controller()
    _, now = run(controller, ahead(1.5), 0.0, 3.0)
    controller.observe(ahead(1.5), now, image_stamp_s=now + 100.0)
    assert controller.command(now + DEFAULTS['detection_timeout']) == (0.0, 0.0)


# Why the command is zero or limited, and fused scans ------------------------------------------

CLEAR_SCAN = (2.0 * np.stack((np.cos(np.radians(np.arange(360))),
                               np.sin(np.radians(np.arange(360)))), axis=1),
              np.zeros(360, bool))
"""A lidar's scan of open floor: no return within 2 m all around."""
TOO_CLOSE = STOP - 0.1
"""A can this far from the robot front: it backs up."""


def drive_toward_can(controller, start_s, duration_s, sources, odometry=True, obstacle=None,
                     gap_m=1.0):
    """Feed a can ``gap_m`` ahead, odometry (unless not) and a clear scan from each of
    ``sources`` (``obstacle``: (source, x m) puts a return there on base_link's x axis in that
    source's scan) at the control rate; the last command."""
    now, command = start_s, None
    while now < start_s + duration_s - 1e-9:
        if odometry:
            controller.observe_pose(Pose2D(0.0, 0.0, 0.0), now)
        for source in sources:
            ends, hits = CLEAR_SCAN
            if obstacle is not None and obstacle[0] == source:
                ends, hits = np.array([[obstacle[1], 0.0]]), np.array([True])
            controller.observe_scan(source, ends, hits, (0.0, 0.0), now)
        controller.observe_camera_info(now)
        controller.observe(ahead(gap_m), now)
        command = controller.command(now)
        now += DT
    return command


def test_why_names_the_missing_odometry_while_the_command_is_zero():
    controller = make_controller(scan_topics='/scan')
    driving = drive_toward_can(controller, 0.0, 1.0, ('/scan',))
    assert driving[0] > 0.1 and controller.reason is None
    assert controller.missing_inputs(1.0) == []
    assert controller.health(1.0).level == OK
    assert controller.health(1.0).message.startswith('APPROACH: commanding 0.')
    stopped = drive_toward_can(controller, 1.0, 1.5, ('/scan',), odometry=False)
    assert stopped == (0.0, 0.0)
    assert controller.state is State.APPROACH
    assert controller.reason.kind is Kind.SENSING_STALE
    assert controller.reason['problems'].startswith('no odometry for ')
    health = controller.health(2.5)
    assert health.level == ERROR
    assert health.message.startswith('APPROACH: no odometry for ')
    assert [(item.name, item.problem) for item in controller.missing_inputs(2.5)] == [
        ('odometry', 'no odometry for 1.55 s (timeout 0.50 s)')]


def test_why_names_a_stale_detection_and_an_unheard_scan():
    controller = make_controller(scan_topics='/scan')
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe_camera_info(0.0)
    controller.observe(ahead(1.0), 0.0)
    assert controller.command(0.0)[0] == 0.0
    assert controller.reason == reason(Kind.SENSING_STALE, problems='no scan on /scan yet')
    assert controller.command(1.0) == (0.0, 0.0)
    assert controller.reason.kind is Kind.INPUTS_MISSING
    assert controller.reason['problems'].startswith('no detection for 1.00 s')


def test_inputs_awaited_since_a_reset_are_overdue_only_after_their_timeout():
    controller = make_controller(scan_topics='/scan')
    controller.reset(10.0)
    awaited = controller.missing_inputs(10.1)
    assert [(item.name, item.overdue) for item in awaited] == [
        ('detection', False), ('odometry', False), ('/scan', False), ('camera_info', False)]
    assert controller.health(10.1).level == WARN
    assert [item.name for item in controller.missing_inputs(10.6) if not item.overdue] == [
        'camera_info']   # its timeout is 1 s
    assert controller.health(10.6).level == ERROR
    assert all(item.overdue for item in controller.missing_inputs(11.1))


def test_why_says_an_obstacle_capped_the_speed():
    controller = make_controller(scan_topics='/scan')
    command = drive_toward_can(controller, 0.0, 2.0, ('/scan',), obstacle=('/scan', -0.27),
                               gap_m=TOO_CLOSE)
    assert command[0] == 0.0
    assert controller.reason.kind is Kind.SPEED_CAPPED and not controller.reason['ahead']
    assert not controller.reason['unknown_floor']


def test_why_says_deadband_then_stopped_at_the_can():
    controller = make_controller()
    controller.observe(ahead(STOP + 0.002), 0.0)
    assert controller.command(0.0) == (0.0, 0.0)
    assert controller.reason.kind is Kind.DEADBAND
    assert controller.reason['gap_error_m'] == pytest.approx(0.002)
    controller.observe(ahead(STOP + 0.002), DT)
    controller.command(DT)
    assert controller.state is State.STOPPED
    controller.observe(ahead(STOP + 0.002), 2 * DT)
    controller.command(2 * DT)
    assert controller.reason.kind is Kind.STOPPED_AT_CAN


@pytest.mark.parametrize('seen_by', ['/camera_scan', '/scan'])
def test_an_obstacle_either_sensor_sees_is_an_obstacle(seen_by):
    sources = ('/camera_scan', '/scan')
    fused = make_controller(scan_topics=' '.join(sources))
    command = drive_toward_can(fused, 0.0, 2.0, sources, obstacle=(seen_by, -0.27),
                               gap_m=TOO_CLOSE)
    unobstructed = drive_toward_can(make_controller(scan_topics=' '.join(sources)), 0.0, 2.0,
                                    sources, gap_m=TOO_CLOSE)
    assert command[0] == 0.0
    assert unobstructed[0] == pytest.approx(-DEFAULTS['max_reverse'])
    assert fused.reason.kind is Kind.SPEED_CAPPED and not fused.reason['ahead']


def test_a_stale_sensor_stops_the_driving_even_when_the_other_is_fresh():
    sources = ('/camera_scan', '/scan')
    controller = make_controller(scan_topics=' '.join(sources))
    assert drive_toward_can(controller, 0.0, 1.0, sources)[0] > 0.1
    command = drive_toward_can(controller, 1.0, 1.0, ('/camera_scan',))
    assert command[0] == 0.0
    assert controller.reason.kind is Kind.SENSING_STALE
    assert controller.reason['problems'].startswith('no scan on /scan for ')
    assert [item.name for item in controller.missing_inputs(2.0)] == ['/scan']


# Close up, the can's base below the image --------------------------------------------------

def approach_with_the_base_leaving_the_image(can_x_m, base_near_m, seen_near_m=None):
    """Drive a unicycle from the origin toward a can ``can_x_m`` ahead, with a camera at
    x = 0.12 whose image's bottom row meets the floor ``base_near_m`` ahead of it: the
    detector ranges the can while its near surface is beyond that, and sees nothing nearer
    (``seen_near_m`` overrides where it stops seeing it). Returns (controller, true gap)."""
    controller = make_controller()
    controller.set_camera_view(CameraView(0.12, 0.0, 0.0, math.radians(29.0), 0.2, 2.5,
                                          base_near_m))
    seen_near_m = base_near_m if seen_near_m is None else seen_near_m
    x_m, now = 0.0, 0.0
    for _ in range(int(20.0 / DT)):
        controller.observe_pose(Pose2D(x_m, 0.0, 0.0), now)
        range_m = can_x_m - x_m - 0.12 - 0.033
        sighting = (Sighting(range_m + 0.12 - 0.165, 0.0) if range_m > seen_near_m else None)
        controller.observe(sighting, now)
        linear, _ = controller.command(now)
        if controller.state is State.STOPPED:
            break
        x_m += linear * DT
        now += DT
    return controller, can_x_m - x_m - 0.033 - 0.165


def test_the_approach_goes_on_by_odometry_once_the_cans_base_is_below_the_image():
    """A camera 0.34 m up pitched 15 deg down (45 deg vertical view) sees the floor from
    0.44 m ahead: at the stop distance (0.3 m from the camera) the can is below its view. The
    approach stops at the position it ranged last, carried by odometry, and stays there."""
    controller, gap_m = approach_with_the_base_leaving_the_image(1.5, 0.44)
    assert controller.state is State.STOPPED
    assert gap_m == pytest.approx(STOP, abs=DEFAULTS['distance_tolerance'])
    assert controller.tracker.below_view(controller.context.camera_view)
    now = 30.0
    for _ in range(int(5.0 / DT)):
        controller.observe(None, now)
        controller.command(now)
        now += DT
    assert controller.state is State.STOPPED


def test_a_can_unseen_where_the_camera_would_see_its_base_is_lost():
    controller, gap_m = approach_with_the_base_leaving_the_image(1.5, 0.44, seen_near_m=0.7)
    assert controller.state is not State.STOPPED
    assert gap_m > 0.5


def test_an_approach_on_a_carried_can_the_camera_would_see_ends_lost_not_stopped():
    """Heading for a stop point aside an obstacle, the approach goes on with where the can was
    ranged last while the camera does not see it. Arrived there with the can in the camera's
    view (not below it) and unseen for longer than VANISH_TIMEOUT_S, the can is not where it was
    ranged (one frame ranged a half-hidden can far off): LOST, never STOPPED."""
    controller = make_controller()
    controller.set_camera_view(CameraView(0.12, 0.0, 0.0, math.radians(29.0), 0.2, 2.5, 0.2))
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe(ahead(STOP + 0.6), 0.0)
    controller.command(0.0)
    assert controller.state is State.APPROACH
    controller.parts.approach.stop_aside.direction_rad = math.pi
    x_m, now = 0.0, DT
    while now < 15.0 and controller.state is State.APPROACH:
        controller.observe_pose(Pose2D(x_m, 0.0, 0.0), now)
        controller.observe(None, now)
        linear, _ = controller.command(now)
        x_m += linear * DT
        now += DT
    assert controller.state is State.LOST, controller.why
    assert x_m > 0.4
    assert controller.reason.kind is Kind.ARRIVED_UNSEEN
    assert controller.reason['unseen_s'] > DEFAULTS['vanish_timeout']


def test_unknown_floor_beside_the_way_ahead_makes_the_robot_turn_to_look():
    """A sensor that sees only a narrow wedge ahead: the floor just beside the way to the can
    is unknown, so the robot does not drive; rather than stand there it turns to look at that
    floor, and drives once a scan has observed it."""
    controller = make_controller(scan_topics='/scan')
    wedge = (CLEAR_SCAN[0][np.abs(np.arctan2(CLEAR_SCAN[0][:, 1], CLEAR_SCAN[0][:, 0]))
                           < math.radians(20.0)],)
    wedge += (np.zeros(len(wedge[0]), bool),)
    now, command = 0.0, None
    for _ in range(10):
        controller.observe_pose(Pose2D(0.0, 0.0, 0.0), now)
        controller.observe_scan('/scan', *wedge, (0.0, 0.0), now, range_min_m=0.1)
        controller.observe_camera_info(now)
        controller.observe(ahead(1.0), now)
        command = controller.command(now)
        now += DT
    assert command[0] == 0.0
    assert abs(command[1]) > 0.0
    assert controller.reason.kind is Kind.SPEED_CAPPED and controller.reason['unknown_floor']
    assert controller.reason['ahead'] and controller.reason['then'] is Then.LOOK
    command = drive_toward_can(controller, now, 1.0, ('/scan',))
    assert command[0] > 0.1 and controller.reason is None


def test_a_late_scan_is_placed_at_the_pose_it_was_taken_from():
    """A camera scan comes as late as its frame: taken at 1.0 facing +x, received at 1.12 after
    a quarter turn, its obstacle 1 m ahead lies at (1, 0) in odom, not at (0, 1)."""
    controller = make_controller(scan_topics='/camera_scan')
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 1.0)
    controller.observe_pose(Pose2D(0.0, 0.0, math.pi / 2.0), 1.12)
    controller.observe_scan('/camera_scan', np.array([[1.0, 0.0]]), np.array([True]),
                            (0.0, 0.0), 1.12, stamp_s=1.0)
    world = controller.navigator.world
    ix, iy = np.nonzero(world.occupied())
    centres = world.centre_of(ix, iy)
    assert len(centres) == 1
    assert centres[0] == pytest.approx((1.0, 0.0), abs=world.resolution_m)


def test_commands_do_not_depend_on_when_the_trial_started():
    """The same inputs at the same times after a trial's start give the same commands bit for
    bit whatever the absolute sim time of the start: the acceleration ramp's step was the
    difference of two absolute stamps, whole nanoseconds rounded from the simulator's time, so
    one frame period came out a nanosecond longer or shorter depending on the start (a 2e-9
    rad/s difference that grew into another course over a long lockstep trial)."""
    def commands(start_s):
        controller = make_controller()
        out = []
        for frame in range(60):
            now = round((start_s + frame / 15.0) * 1e9) * 1e-9   # a ROS stamp: whole ns
            controller.observe_pose(Pose2D(0.0, 0.0, 0.0), now)
            controller.observe(None if frame < 20 else ahead(1.5, 20.0), now, now)
            out.append(controller.command(now))
        return out

    assert commands(1.2208333333333334) == commands(1.4208333333333334)


def backing_up_to_see(view, unknown_x, unknown_y, obstacle_behind=False, duration_s=8.0):
    """Drive toward a can 1 m ahead seen by ``view``, with the floor in the box ``unknown_x``
    by ``unknown_y`` (base_link, m) never observed and the floor behind observed by a scan,
    until the robot first drives forward after backing up: (controller, x m, commands,
    reasons, time s)."""
    controller = make_controller(scan_topics='/scan')
    controller.set_camera_view(view)
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe_scan('/scan', *CLEAR_SCAN, (0.0, 0.0), 0.0)
    world = controller.navigator.world
    fine = np.arange(world.floor.observed.shape[0]) * world.observed_resolution_m + world.origin_m
    ahead_x = (fine >= unknown_x[0]) & (fine < unknown_x[1])
    beside_y = (fine >= unknown_y[0]) & (fine < unknown_y[1])
    world.floor.observed[np.ix_(ahead_x, beside_y)] = False
    rear = CLEAR_SCAN[0][:, 0] < -0.1
    ends, hits = CLEAR_SCAN[0][rear], CLEAR_SCAN[1][rear]
    if obstacle_behind:
        ends, hits = np.vstack((ends, [[-0.3, 0.0]])), np.append(hits, True)
    x_m, now, commands, reasons = 0.0, 0.0, [], []
    for _ in range(int(duration_s / DT)):
        controller.observe_pose(Pose2D(x_m, 0.0, 0.0), now)
        controller.observe_scan('/scan', ends, hits, (0.0, 0.0), now)
        controller.observe_camera_info(now)
        controller.observe(Sighting(1.0 - x_m, 0.0), now)
        commands.append(controller.command(now))
        reasons.append(controller.reason)
        if len(commands) > 5 and commands[-1][0] >= 0.0 and commands[-2][0] < 0.0:
            break
        x_m += commands[-1][0] * DT
        now += DT
    return controller, x_m, commands, reasons, now


def drive_on_with_the_floor_observed(controller, x_m, now):
    """Two more seconds with a scan that observes all the floor: (last command, x m)."""
    for _ in range(int(2.0 / DT)):
        controller.observe_pose(Pose2D(x_m, 0.0, 0.0), now)
        controller.observe_scan('/scan', *CLEAR_SCAN, (0.0, 0.0), now)
        controller.observe_camera_info(now)
        controller.observe(Sighting(1.0 - x_m, 0.0), now)
        command = controller.command(now)
        x_m += command[0] * DT
        now += DT
    return command, x_m


def test_unknown_floor_below_the_cameras_view_makes_the_robot_back_up_to_see_it():
    """The image's bottom row meets the floor 0.5 m ahead of the camera: floor just in front of
    the robot that no sensor has observed stays below the view however the robot turns, so the
    robot backs up (floor behind it observed) until that floor is 5 cm inside the view, and
    drives on once a scan has observed it; with an obstacle behind it, it turns to look
    instead."""
    view = CameraView(0.12, 0.0, 0.0, math.radians(29.0), 0.2, 2.5, 0.5)
    controller, x_m, commands, reasons, now = backing_up_to_see(view, (0.2, 0.45), (-0.2, 0.2))
    assert reasons[0]['then'] is Then.BACK_UP
    assert commands[20] == (pytest.approx(-DEFAULTS['max_reverse']), 0.0)
    assert reasons[20].kind is Kind.BACKING_TO_SEE
    # then the unknown floor's nearest cells (0.2 m ahead of base_link, 0.08 m ahead of the
    # camera) are half a cell and 5 cm beyond the bottom row's 0.5 m (to a tick's travel)
    assert 0.45 < -x_m < 0.52
    command, _ = drive_on_with_the_floor_observed(controller, x_m, now)
    assert command[0] > 0.1 and controller.reason is None

    controller, x_m, commands, reasons, _ = backing_up_to_see(view, (0.2, 0.45), (-0.2, 0.2),
                                                              obstacle_behind=True)
    assert len(commands) == int(8.0 / DT)
    assert x_m == 0.0 and all(command[0] == 0.0 for command in commands)
    assert abs(commands[-1][1]) > 0.0 and reasons[-1]['then'] is Then.LOOK


def test_unknown_floor_beside_the_front_backs_a_steep_camera_up_until_the_view_is_wide_enough():
    """A camera 0.18 m up pitched 34 deg down sees the floor from 0.12 m ahead of it, but only
    0.11 m either side there, narrower than the robot (0.165 m radius), and 0.45 m wider per m
    farther. Floor never observed beside the robot's front, 0.12-0.25 m to the left, comes
    into view only once the robot has backed up about 0.4 m; backing up till it is 5 cm
    beyond the bottom row, as for floor dead ahead, left it outside the view, and the robot
    went back and forth in place."""
    pose = camera_pose_from_mount(CameraMount(0.18, 34.3))
    view = camera_view(pose, intrinsics_from_vertical_fov(320, 240, 45.0), 2.5, 0.122)
    assert view.base_half_width_m == pytest.approx(0.11, abs=0.005)
    assert view.side_slope == pytest.approx(0.45, abs=0.01)
    controller, x_m, commands, reasons, now = backing_up_to_see(view, (0.1, 0.3), (0.12, 0.25))
    assert reasons[0]['then'] is Then.BACK_UP
    assert 0.3 < -x_m < 0.5
    command, driven_x_m = drive_on_with_the_floor_observed(controller, x_m, now)
    assert driven_x_m > x_m + 0.1 and command[0] > 0.1 and controller.reason is None


def test_one_input_timeout_bounds_every_input_camera_info_at_twice_it():
    settings = controller_settings(read_with('input_timeout', 0.3)[0])
    assert (settings.detection_timeout, settings.scan_timeout, settings.odom_timeout) == (
        0.3, 0.3, 0.3)
    assert settings.camera_info_timeout == pytest.approx(0.6)


def test_exploring_cruises_at_its_speed_or_at_a_lower_max_linear():
    assert controller_settings(read_with('max_linear', 0.4)[0]).explore_linear == 0.3
    assert controller_settings(read_with('max_linear', 0.22)[0]).explore_linear == 0.22
