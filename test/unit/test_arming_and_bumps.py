"""can_stopper's controller armed on request, searching without exploring, camera_info as a
named input, and the bump recovery."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from can_seeker.control.bump_recovery import BACK_OFF_M, BACK_OFF_MPS, BumpRecovery
from can_seeker.control.controller import PARAMS, Controller
from can_seeker.control.tuning import controller_settings
from can_seeker.control.reasons import Kind, reason
from can_seeker.control.sighting import Sighting
from can_seeker.control.supervisor import State
from can_seeker.control.navigation import CameraView, Pose2D
from can_seeker.health import ERROR, OK, WARN
from can_seeker.params import defaults

DEFAULTS = vars(controller_settings(defaults(PARAMS)))
DT = 1.0 / DEFAULTS['rate']
ROBOT_RADIUS = DEFAULTS['robot_radius']
CLEAR_SCAN = (2.0 * np.stack((np.cos(np.radians(np.arange(360))),
                               np.sin(np.radians(np.arange(360)))), axis=1),
              np.zeros(360, bool))
"""A lidar's scan of open floor: no return within 2 m all around."""


def make_controller(**overrides):
    """A controller with a lidar on /scan, unless overridden."""
    return Controller(SimpleNamespace(**{**DEFAULTS, 'scan_topics': '/scan', **overrides}),
                      camera_info_topic='/robot1/camera/camera_info',
                      arm_hint='rosservice call /robot1/can_stopper/enable true')


def feed(controller, start_s, duration_s, sighting=None, camera_info=True, pose=None,
         drive=False):
    """Odometry, a clear scan, camera_info (unless not) and ``sighting`` at the control rate;
    with ``drive`` the robot moves by its commands (a unicycle from ``pose``). Returns
    (commands, pose, end time)."""
    pose = pose or Pose2D(0.0, 0.0, 0.0)
    now, commands = start_s, []
    while now < start_s + duration_s - 1e-9:
        controller.observe_pose(pose, now)
        controller.observe_scan('/scan', *CLEAR_SCAN, (0.0, 0.0), now)
        if camera_info:
            controller.observe_camera_info(now)
        controller.observe(sighting, now)
        commands.append(controller.command(now))
        if drive:
            linear, angular = commands[-1]
            pose = Pose2D(pose.x + linear * DT * math.cos(pose.yaw),
                          pose.y + linear * DT * math.sin(pose.yaw), pose.yaw + angular * DT)
        now += DT
    return commands, pose, now


# Armed on request ---------------------------------------------------------------------------

def test_armed_by_default_disarmed_starts_idle_with_zero_commands():
    assert make_controller().state is State.SEARCH
    controller = make_controller(enabled=False)
    assert controller.state is State.IDLE
    commands, _, now = feed(controller, 0.0, 2.0, Sighting(1.0, 0.0))
    assert set(commands) == {(0.0, 0.0)}
    assert controller.state is State.IDLE
    assert controller.reason == reason(Kind.DISARMED,
                                       arm_hint='rosservice call /robot1/can_stopper/enable true')
    health = controller.health(now)
    assert health.message.startswith('IDLE: disarmed')
    assert dict(health.values)['armed'] == 'no'
    assert health.level == OK


def test_disarmed_missing_inputs_are_at_most_a_warning():
    controller = make_controller(enabled=False)
    assert controller.missing_inputs(5.0)
    assert controller.health(5.0).level == WARN
    assert make_controller().health(5.0).level == ERROR


def test_arming_searches_afresh_and_disarming_stops_at_once():
    controller = make_controller(enabled=False)
    feed(controller, 0.0, 1.0, Sighting(1.0, 0.0))
    controller.navigator.world.add_contact((1.0, 0.0))
    assert controller.set_enabled(True, 1.0) == 'armed: SEARCH'
    assert controller.state is State.SEARCH
    assert not controller.navigator.world.occupied().any()
    commands, _, now = feed(controller, 1.0, 3.0, Sighting(1.0, 0.0))
    assert controller.state is State.APPROACH
    assert commands[-1][0] > 0.2
    assert controller.set_enabled(True, now) == 'already armed'
    assert controller.state is State.APPROACH
    assert controller.set_enabled(False, now).startswith('disarmed')
    assert controller.state is State.IDLE
    # no ramp-down within the acceleration limit: the very next command is zero
    commands, _, now = feed(controller, now, 1.0, Sighting(1.0, 0.0))
    assert set(commands) == {(0.0, 0.0)}


def test_reset_while_disarmed_stays_idle():
    controller = make_controller(enabled=False)
    controller.reset(1.0)
    assert controller.state is State.IDLE
    assert controller.reason.kind is Kind.DISARMED


def test_a_bump_while_disarmed_starts_no_recovery():
    controller = make_controller(enabled=False)
    feed(controller, 0.0, 0.5)
    assert not controller.observe_bump(True, 0.5)
    assert not controller.navigator.world.obstacles.contact.any()


# Searching without exploring ----------------------------------------------------------------

def test_without_explore_search_turns_in_place_after_a_full_turn():
    def two_turns(explore):
        """(states, commands, end pose) of two full turns' time without a can."""
        controller = make_controller(explore=explore)
        controller.set_camera_view(CameraView(0.12, 0.0, 0.0, math.radians(29.0), 0.2, 2.5,
                                              0.3))
        states, commands, pose, now = [], [], None, 0.0
        for _ in range(int(2.2 * 2.0 * math.pi / DEFAULTS['search_angular'] / DT)):
            tick, pose, now = feed(controller, now, DT, pose=pose, drive=True)
            commands += tick
            states.append(controller.state)
        return controller, states, commands, pose

    _, states, _, _ = two_turns(True)
    assert State.EXPLORE in states
    turning, states, commands, pose = two_turns(False)
    assert set(states) == {State.SEARCH}
    assert all(linear == 0.0 for linear, _ in commands)
    assert (pose.x, pose.y) == (0.0, 0.0)
    assert turning.reason.kind is Kind.EXPLORE_OFF


def test_without_explore_the_robot_still_approaches_a_can_it_sees():
    controller = make_controller(explore=False)
    commands, _, _ = feed(controller, 0.0, 2.0, Sighting(1.0, 0.0))
    assert controller.state is State.APPROACH
    assert commands[-1][0] > 0.2


# camera_info, a named input -----------------------------------------------------------------

def test_without_camera_info_the_robot_only_turns_and_says_so():
    controller = make_controller()
    commands, _, now = feed(controller, 0.0, 2.0, Sighting(1.0, math.radians(10.0)),
                            camera_info=False)
    assert controller.state is State.APPROACH
    assert all(linear == 0.0 for linear, _ in commands)
    assert commands[-1][1] > 0.0
    assert controller.reason == reason(Kind.SENSING_STALE,
                                       problems='no camera_info on /robot1/camera/camera_info yet')
    missing = controller.missing_inputs(now)
    assert [item.name for item in missing] == ['camera_info']
    assert dict(controller.health(now).values)['missing inputs'] == \
        'no camera_info on /robot1/camera/camera_info yet'
    assert controller.health(now).level == ERROR


def test_stale_camera_info_stops_the_driving_and_fresh_camera_info_lets_it_go_on():
    controller = make_controller()
    commands, _, now = feed(controller, 0.0, 2.0, Sighting(1.0, 0.0))
    assert commands[-1][0] > 0.2
    commands, _, now = feed(controller, now, 2.0, Sighting(1.0, 0.0), camera_info=False)
    assert commands[-1] == (0.0, 0.0)
    assert controller.reason.kind is Kind.SENSING_STALE
    problems = controller.reason['problems']
    assert problems.startswith('no camera_info on /robot1/camera/camera_info for ')
    assert '(timeout 1.00 s)' in problems
    commands, _, now = feed(controller, now, 1.0, Sighting(1.0, 0.0))
    assert commands[-1][0] > 0.1 and controller.missing_inputs(now) == []


@pytest.mark.parametrize('overrides', [{'scan_topics': ''}, {'behaviour': 'wander'}])
def test_camera_info_is_no_input_without_obstacle_sensing_or_in_wander(overrides):
    controller = make_controller(**overrides)
    feed(controller, 0.0, 2.0, Sighting(1.0, 0.0), camera_info=False)
    assert 'camera_info' not in [item.name for item in controller.missing_inputs(2.0)]


# The bump recovery ----------------------------------------------------------------------------

def test_bump_recovery_marks_the_front_and_backs_off_then_hands_back():
    recovery = BumpRecovery(ROBOT_RADIUS, 0.1)
    pose = Pose2D(1.0, 2.0, math.pi / 2.0)
    contact = recovery.bumped(True, pose, 0.0)
    assert contact == pytest.approx((1.0, 2.0 + ROBOT_RADIUS))
    assert recovery.bumped(True, pose, 0.02) is None   # still the same touch
    command, why = recovery.command(pose, 0.02)
    assert command == (-BACK_OFF_MPS, 0.0)
    assert why.kind is Kind.BUMPED and why['backed_m'] == 0.0 and why['back_off_m'] == BACK_OFF_M
    backed = Pose2D(1.0, 2.0 - BACK_OFF_M, math.pi / 2.0)
    assert recovery.command(backed, 2.5) is None
    assert not recovery.active and recovery.count == 1


def test_bump_recovery_gives_up_when_the_robot_cannot_back_off():
    recovery = BumpRecovery(ROBOT_RADIUS, 0.1)
    pose = Pose2D(0.0, 0.0, 0.0)
    recovery.bumped(True, pose, 0.0)
    assert recovery.command(pose, BACK_OFF_M / BACK_OFF_MPS + 1.0) is not None
    assert recovery.command(pose, BACK_OFF_M / BACK_OFF_MPS + 3.5) is None


def test_bump_recovery_without_reverse_only_stops():
    recovery = BumpRecovery(ROBOT_RADIUS, 0.0)
    recovery.bumped(True, Pose2D(0.0, 0.0, 0.0), 0.0)
    assert recovery.command(Pose2D(0.0, 0.0, 0.0), 0.05) is None


def test_a_contact_stays_in_the_map_whatever_scans_see_there():
    controller = make_controller()
    feed(controller, 0.0, 0.5)
    world = controller.navigator.world
    world.add_contact((0.5, 0.0))
    feed(controller, 0.5, 30.0)   # free rays through it, longer than OBSTACLE_MEMORY_S
    cell = world.cell_of(0.5, 0.0)
    assert world.occupied()[cell] and world.obstacles.evidence[cell] < 0
    points, _ = controller.navigator.obstacles_base()
    assert np.any(np.all(np.isclose(points, (0.5, 0.0)), axis=1))


def test_a_bump_stops_at_once_backs_off_slowly_and_the_robot_keeps_off_the_contact():
    """Driving at a can 1.5 m ahead behind something no sensor sees, 0.6 m ahead: the bump
    stops the robot at once, it backs off BACK_OFF_M within the limits, the contact is kept in
    front of where it touched, and the robot does not drive into it again."""
    controller = make_controller()
    commands, pose, now = feed(controller, 0.0, 1.2, Sighting(1.3, 0.0), drive=True)
    assert commands[-1][0] > 0.2
    pressed_at = pose
    assert controller.observe_bump(True, now)
    assert controller.last_command == (0.0, 0.0)
    assert controller.navigator.world.obstacles.contact[controller.navigator.world.cell_of(
        pressed_at.x + ROBOT_RADIUS, 0.0)]
    commands, pose, now = feed(controller, now, 0.2, Sighting(1.3 - pose.x, 0.0), pose=pose,
                               drive=True)
    assert all(-BACK_OFF_MPS - 1e-9 <= linear <= 0.0 for linear, _ in commands)
    assert commands[0][0] == pytest.approx(-DEFAULTS['max_linear_accel'] * DT)
    assert controller.reason.kind is Kind.BUMPED
    controller.observe_bump(False, now)
    commands, pose, now = feed(controller, now, 10.0, Sighting(1.3 - pose.x, 0.0), pose=pose,
                               drive=True)
    assert pose.x < pressed_at.x - BACK_OFF_M / 2.0 or abs(pose.y) > 0.05
    contact_x = pressed_at.x + ROBOT_RADIUS
    assert math.hypot(pose.x - contact_x, pose.y) > ROBOT_RADIUS
    assert controller.parts.bump.count == 1
    assert dict(controller.health(now).values)['bumps'] == '1'
