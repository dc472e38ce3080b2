"""Each behaviour on its own: small scenarios of its command, its reasons and the events it
reports to the supervisor (the parts wired as the controller wires them)."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from can_seeker.control.controller import PARAMS, Controller
from can_seeker.control.tuning import controller_settings
from can_seeker.control.navigation import Pose2D
from can_seeker.control.reasons import Because, Consequence, Kind
from can_seeker.control.sighting import Sighting
from can_seeker.control.supervisor import TRANSITIONS, Event, State
from can_seeker.params import defaults

DEFAULTS = vars(controller_settings(defaults(PARAMS)))
STOP = DEFAULTS['stop_distance']


def parts(**overrides):
    """The controller's parts, its pose at the origin, a fresh tick's reasons."""
    controller = Controller(SimpleNamespace(**{**DEFAULTS, 'scan_topics': '', **overrides}))
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.context.because = Because()
    return controller, controller.parts


ALL_ROUND = 2.0 * np.stack((np.cos(np.radians(np.arange(0.0, 360.0, 2.0))),
                             np.sin(np.radians(np.arange(0.0, 360.0, 2.0)))), axis=-1)
"""Rays all round, 2 m long: free floor about the robot."""


def sensing(controller, now_s=0.0, ends=ALL_ROUND, hits=None):
    """Fresh odometry, scan (free floor all round unless told) and camera_info at ``now_s``."""
    controller.observe_pose(controller.navigator.pose, now_s)
    hits = np.zeros(len(ends), bool) if hits is None else np.array(hits)
    controller.observe_scan(controller.scan_sources[0], np.array(ends, float), hits,
                            (0.0, 0.0), now_s)
    controller.observe_camera_info(now_s)


def enter(controller, state, now_s=0.0):
    """Put the supervisor in ``state`` the way the table gets there from where it is."""
    route = {State.APPROACH: [Event.CAN_RANGED], State.EXPLORE: [Event.SEARCHED_ALL_ROUND],
             State.STOPPED: [Event.CAN_RANGED, Event.SETTLED],
             State.LOST: [Event.CAN_RANGED, Event.CAN_OUT_OF_RANGE]}[state]
    for event in route:
        if (controller.state, event) in TRANSITIONS:
            controller.supervisor.handle(event, now_s)
    assert controller.state is state


# SEARCH --------------------------------------------------------------------------------------

def test_search_turns_toward_the_side_the_can_was_seen_on():
    controller, p = parts()
    search = p.supervisor.behaviours[State.SEARCH]
    assert search.command(0.0).command == (0.0, DEFAULTS['search_angular'])
    p.tracker.turn_sign = -1.0
    assert search.command(0.0).command == (0.0, -DEFAULTS['search_angular'])


def test_search_counts_its_turn_and_hands_over_to_explore_after_a_full_one():
    controller, p = parts(scan_topics='scan')
    search = p.supervisor.behaviours[State.SEARCH]
    for step in range(1, 66):                        # 65 x 0.1 rad > 2 pi
        controller.observe_pose(Pose2D(0.0, 0.0, 0.1 * step), 0.05 * step)
    sensing(controller, 3.3)
    result = search.command(3.3)
    assert result == (None, Event.SEARCHED_ALL_ROUND)


def test_search_without_explore_or_navigation_turns_on_and_says_why():
    controller, p = parts(explore=False)
    search = p.supervisor.behaviours[State.SEARCH]
    search.searched_rad = 2.0 * math.pi
    assert search.command(0.0).event is None
    assert p.context.because.first.kind is Kind.EXPLORE_OFF
    controller, p = parts()
    p.supervisor.behaviours[State.SEARCH].searched_rad = 2.0 * math.pi
    p.supervisor.behaviours[State.SEARCH].command(0.0)
    assert p.context.because.first.kind is Kind.CANNOT_NAVIGATE
    assert p.context.because.first['consequence'] is Consequence.SEARCH_ON
    assert p.context.because.first['problems'] == ''      # no obstacle sensing at all


def test_search_explore_and_lost_approach_a_ranged_can():
    controller, p = parts()
    for state in (State.SEARCH, State.EXPLORE, State.LOST):
        behaviour = p.supervisor.behaviours[state]
        assert behaviour.on_detection(True, 0.0) is Event.CAN_RANGED
        assert behaviour.on_detection(False, 0.0) is None


# EXPLORE -------------------------------------------------------------------------------------

def test_explore_without_fresh_sensing_stands_and_says_why():
    controller, p = parts(scan_topics='scan')
    enter(controller, State.EXPLORE)
    result = p.explore.command(5.0)
    assert result.command == (0.0, 0.0) and result.event is None
    assert p.context.because.first['consequence'] is Consequence.NO_EXPLORING
    assert 'odometry' in p.context.because.first['problems']


def test_explore_with_nothing_left_to_cover_forgets_coverage_and_searches_again():
    controller, p = parts(scan_topics='scan')
    enter(controller, State.EXPLORE)
    sensing(controller)
    controller.navigator.world.coverage.seen[:] = True
    result = p.explore.command(0.0)
    assert result.event is Event.NOTHING_TO_EXPLORE
    assert result.command == (0.0, DEFAULTS['search_angular'])
    assert not controller.navigator.world.coverage.seen.any()


def test_explore_at_its_goal_searches_again():
    controller, p = parts(scan_topics='scan')
    enter(controller, State.EXPLORE)
    p.explore.goal_xy = np.array([1.0, 0.0])                 # floor the camera has not covered
    p.paths.planned_s = 0.0
    sensing(controller, 0.05)
    assert p.explore.command(0.05).event is None
    controller.observe_pose(Pose2D(0.95, 0.0, 0.0), 0.1)
    sensing(controller, 0.1)
    result = p.explore.command(0.1)
    assert result.event is Event.GOAL_REACHED
    assert result.command == (0.0, DEFAULTS['search_angular'])


# APPROACH ------------------------------------------------------------------------------------

def ranged(controller, gap_m, bearing_deg=0.0, now_s=0.0):
    controller.observe(Sighting(gap_m, math.radians(bearing_deg)), now_s)


def test_approach_drives_straight_at_a_can_ahead_and_turns_in_place_at_one_beside():
    controller, p = parts()
    ranged(controller, 1.0)
    assert controller.state is State.APPROACH
    linear, angular = p.approach.command(0.0).command
    assert linear > 0.3 and angular == 0.0
    ranged(controller, 1.0, 60.0)
    linear, angular = p.approach.command(0.0).command
    assert linear == 0.0 and angular > 0.0
    assert p.context.because.first.kind is Kind.TURNING_TO_CAN


def test_approach_settles_only_at_rest_within_both_tolerances():
    controller, p = parts()
    ranged(controller, STOP + 0.002)
    assert p.approach.finished((0.0, 0.0), 0.0) is Event.SETTLED
    assert p.approach.finished((0.01, 0.0), 0.0) is None
    ranged(controller, STOP + 0.002, 3.0)
    assert p.approach.finished((0.0, 0.0), 0.0) is None


def test_approach_in_the_stop_band_stands_in_the_deadband():
    controller, p = parts()
    ranged(controller, STOP + 0.002)
    assert p.approach.command(0.0).command == (0.0, 0.0)
    reason = p.context.because.first
    assert reason.kind is Kind.DEADBAND and reason['gap_error_m'] == pytest.approx(0.002)


def test_approach_loses_a_can_that_is_not_ranged():
    controller, p = parts()
    ranged(controller, 1.0)
    assert p.approach.on_detection(False, 0.0) is Event.CAN_OUT_OF_RANGE
    assert p.approach.on_detection(True, 0.0) is None


# STOPPED -------------------------------------------------------------------------------------

def test_stopped_holds_zero_and_says_so():
    controller, p = parts()
    stopped = p.supervisor.behaviours[State.STOPPED]
    assert stopped.command(0.0).command == (0.0, 0.0)
    assert p.context.because.first.kind is Kind.STOPPED_AT_CAN


def test_stopped_approaches_again_when_the_can_moved_and_is_lost_when_it_vanished():
    controller, p = parts()
    ranged(controller, STOP)
    enter(controller, State.STOPPED, 1.0)
    stopped = p.supervisor.behaviours[State.STOPPED]
    assert stopped.on_detection(True, 1.1) is None
    ranged(controller, STOP + 2.0 * DEFAULTS['reapproach_distance'], 0.0, 1.2)
    assert controller.state is State.APPROACH
    enter(controller, State.STOPPED, 2.0)
    assert stopped.on_detection(False, 2.0 + DEFAULTS['vanish_timeout']) is None
    assert stopped.on_detection(False, 2.1 + DEFAULTS['vanish_timeout']) is Event.CAN_VANISHED


# LOST ----------------------------------------------------------------------------------------

def test_lost_times_out_into_search():
    controller, p = parts()
    enter(controller, State.LOST, 1.0)
    lost = p.supervisor.behaviours[State.LOST]
    assert lost.expired(1.0 + DEFAULTS['lost_timeout']) is None
    assert lost.expired(1.1 + DEFAULTS['lost_timeout']) is Event.LOST_TIMEOUT


def test_lost_keeps_heading_for_the_cans_place_while_it_gets_nearer():
    """A long way back to where the can was seen is no reason to give it up; standing is."""
    controller, p = parts()
    ranged(controller, 3.0)
    controller.supervisor.handle(Event.CAN_OUT_OF_RANGE, 0.0)
    lost = p.supervisor.behaviours[State.LOST]
    timeout_s = DEFAULTS['lost_timeout']
    for step in range(4):
        now_s = step * 0.8 * timeout_s
        controller.observe_pose(Pose2D(0.3 * step, 0.0, 0.0), now_s)
        assert lost.expired(now_s) is None
    standing_since_s = 3 * 0.8 * timeout_s
    assert lost.expired(standing_since_s + timeout_s) is None
    assert lost.expired(standing_since_s + timeout_s + 0.1) is Event.LOST_TIMEOUT


def test_lost_without_navigation_turns_toward_the_side_the_can_left():
    controller, p = parts()
    ranged(controller, 1.0, -10.0)
    enter(controller, State.LOST)
    result = p.supervisor.behaviours[State.LOST].command(0.0)
    assert result.command == (0.0, -DEFAULTS['search_angular'])
    assert p.context.because.first['consequence'] is Consequence.TURN_TO_LAST_SEEN


def test_lost_facing_the_cans_place_for_a_second_finds_it_is_not_there():
    controller, p = parts(scan_topics='scan')
    sensing(controller)
    ranged(controller, STOP)
    controller.supervisor.handle(Event.CAN_OUT_OF_RANGE, 0.0)
    lost = p.supervisor.behaviours[State.LOST]
    for now in (0.0, 0.5):
        sensing(controller, now)
        assert lost.command(now).event is None
        assert p.context.because.first.kind is Kind.FACING_LAST_SEEN
    sensing(controller, 1.0)
    p.context.because = Because()
    assert lost.command(1.0).event is Event.CAN_NOT_THERE
    assert p.context.because.first.kind is Kind.CAN_NOT_THERE


# WANDER and IDLE -----------------------------------------------------------------------------

def test_wander_drives_on_while_clear_and_turns_away_from_an_obstacle_ahead():
    controller, p = parts(behaviour='wander', scan_topics='scan')
    wander = p.supervisor.behaviours[State.WANDER]
    assert controller.state is State.WANDER
    sensing(controller)
    assert wander.command(0.0).command == (DEFAULTS['explore_linear'], 0.0)
    sensing(controller, 0.05, ends=((0.4, -0.05),), hits=(True,))
    linear, angular = wander.command(0.05).command
    assert linear == 0.0 and angular == DEFAULTS['search_angular']   # away from the right
    p.context.last_command = (0.0, -0.3)
    assert wander.command(0.1).command == (0.0, -DEFAULTS['search_angular'])   # keeps turning


def test_idle_commands_zero():
    controller, p = parts(enabled=False)
    assert controller.state is State.IDLE
    assert p.supervisor.behaviour.command(0.0).command == (0.0, 0.0)
