"""Each recovery on its own: the floor recoveries (back up to see floor below the camera's
view, turn to look at unknown floor) and the stall watchdogs (keep to the path, give up a
goal), with the parts wired as the controller wires them."""
import math
from types import SimpleNamespace

import numpy as np

from can_seeker.control.controller import PARAMS, Controller
from can_seeker.control.tuning import controller_settings
from can_seeker.control.navigation import CameraView, Pose2D
from can_seeker.control.reasons import Because, Kind, Then
from can_seeker.control.recoveries.floor import BACK_UP_BEYOND_M, TurnToLook
from can_seeker.control.recoveries.stall import (APPROACH_STALL_BEYOND_MEMORY_S, STALL_S,
                                                 GiveUpGoal)
from can_seeker.control.safety_filter import Verdict
from can_seeker.control.sighting import Sighting
from can_seeker.control.supervisor import Event, State
from can_seeker.params import defaults

DEFAULTS = vars(controller_settings(defaults(PARAMS)))
STEEP_VIEW = CameraView(0.12, 0.0, 0.0, math.radians(29.0), 0.12, 2.5, 0.23)
"""A camera whose image's bottom row meets the floor 0.23 m ahead of it."""


def make(**overrides):
    """The controller's parts at the origin, the floor about it observed free for 1.5 m."""
    controller = Controller(SimpleNamespace(**{**DEFAULTS, **overrides}))
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    angles = np.radians(np.arange(0.0, 360.0, 1.0))
    ends = 1.5 * np.stack((np.cos(angles), np.sin(angles)), axis=-1)
    controller.observe_scan(controller.scan_sources[0], ends, np.zeros(len(angles), bool),
                            (0.0, 0.0), 0.0)
    return controller, controller.parts


def blocked_at(point):
    """The safety filter's verdict on a forward command held back by unknown floor."""
    return Verdict(0.0, 0.01, np.array(point, float), True)


# BackUpToSeeFloor -----------------------------------------------------------------------------

def test_back_up_starts_for_floor_below_the_view_and_goes_on_until_far_enough():
    controller, p = make()
    controller.set_camera_view(STEEP_VIEW)
    found = p.back_up.unblock((0.2, 0.0), blocked_at((0.2, 0.15)), None)
    assert found is not None
    command, then = found
    assert command == (-DEFAULTS['max_reverse'], 0.0) and then is Then.BACK_UP
    total_m = p.back_up.backing[2]
    assert total_m > BACK_UP_BEYOND_M
    command, why = p.back_up.resume(None)
    assert command == (-DEFAULTS['max_reverse'], 0.0)
    assert why.kind is Kind.BACKING_TO_SEE and why['backed_m'] == 0.0
    controller.observe_pose(Pose2D(-total_m, 0.0, 0.0), 1.0)
    assert p.back_up.resume(None) is None and p.back_up.backing is None


def test_back_up_does_nothing_for_floor_in_view_or_without_a_view():
    controller, p = make()
    assert p.back_up.unblock((0.2, 0.0), blocked_at((0.2, 0.15)), None) is None
    controller.set_camera_view(STEEP_VIEW)
    assert p.back_up.unblock((0.2, 0.0), blocked_at((1.0, 0.0)), None) is None


def test_a_state_change_ends_the_back_up():
    controller, p = make()
    controller.set_camera_view(STEEP_VIEW)
    p.back_up.unblock((0.2, 0.0), blocked_at((0.2, 0.15)), None)
    controller.supervisor.handle(Event.CAN_RANGED, 0.0)
    assert p.back_up.backing is None


# TurnToLook -----------------------------------------------------------------------------------

def test_turn_to_look_turns_toward_the_unknown_floor_unless_turning_already():
    look = TurnToLook(SimpleNamespace(**DEFAULTS))
    search = DEFAULTS['search_angular']
    assert look.unblock((0.2, 0.0), blocked_at((0.3, -0.2)), None) == ((0.0, -search),
                                                                         Then.LOOK)
    assert look.unblock((0.2, 0.1), blocked_at((0.3, 0.0)), None) == ((0.0, search), Then.LOOK)
    assert look.unblock((0.2, 0.6 * search), blocked_at((0.3, -0.2)), None) is None


# KeepToPath -----------------------------------------------------------------------------------

def approaching(controller, gap_m=1.8):
    controller.observe(Sighting(gap_m, 0.0, 1.0), 0.0)
    assert controller.state is State.APPROACH


def test_keep_to_path_switches_after_a_stall_and_back_after_another():
    controller, p = make()
    approaching(controller)
    keep = p.keep_to_path
    stall_s = DEFAULTS['obstacle_memory'] + APPROACH_STALL_BEYOND_MEMORY_S
    because = Because()
    keep.after_tick(State.APPROACH, 0.0, because)
    keep.after_tick(State.APPROACH, stall_s, because)
    assert not keep.active and because.first is None
    keep.after_tick(State.APPROACH, stall_s + 0.1, because)
    assert keep.active and keep.keeping()
    assert because.first.kind is Kind.APPROACH_STALLED and because.first['keep_to_path']
    keep.after_tick(State.APPROACH, 2 * stall_s + 0.2, Because())
    assert not keep.active


def test_keep_to_path_spans_approach_and_lost_and_ends_elsewhere():
    controller, p = make()
    approaching(controller)
    p.keep_to_path.active = True
    controller.observe(None, 0.1)                  # kept to the path: the can is carried
    assert controller.state is State.APPROACH
    controller.supervisor.handle(Event.CAN_OUT_OF_RANGE, 0.2)
    assert p.keep_to_path.active
    controller.supervisor.handle(Event.LOST_TIMEOUT, 0.3)
    assert not p.keep_to_path.active


def test_keep_to_path_counts_no_stall_within_the_direct_gap():
    controller, p = make()
    approaching(controller, gap_m=0.4)
    keep = p.keep_to_path
    for now in range(0, 60, 5):
        keep.after_tick(State.APPROACH, float(now), Because())
    assert not keep.active


# GiveUpGoal -----------------------------------------------------------------------------------

def test_give_up_goal_after_a_stall_without_new_coverage():
    controller, p = make()
    controller.supervisor.handle(Event.SEARCHED_ALL_ROUND, 0.0)
    p.explore.goal_xy = np.array([2.0, 0.0])
    give_up = p.give_up
    assert isinstance(give_up, GiveUpGoal)
    give_up.after_tick(State.EXPLORE, 0.0, Because())
    give_up.after_tick(State.EXPLORE, STALL_S, Because())
    assert p.explore.goal_xy is not None
    give_up.after_tick(State.EXPLORE, STALL_S + 0.1, Because())
    assert p.explore.goal_xy is None


def test_give_up_goal_waits_while_the_camera_covers_new_floor():
    controller, p = make()
    controller.supervisor.handle(Event.SEARCHED_ALL_ROUND, 0.0)
    p.explore.goal_xy = np.array([2.0, 0.0])
    world = controller.navigator.world
    for step in range(20):
        world.coverage.seen.flat[10 * step:10 * step + 10] = True
        p.give_up.after_tick(State.EXPLORE, 1.0 * step, Because())
    assert p.explore.goal_xy is not None
