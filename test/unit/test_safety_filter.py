"""The stateless safety filter, and the reasons it gives (their text made in one place)."""
import math
from types import SimpleNamespace

import numpy as np

from can_seeker.control.controller import PARAMS
from can_seeker.control.tuning import controller_settings
from can_seeker.control.input_freshness import MissingInput
from can_seeker.control.navigation import Navigator, Pose2D
from can_seeker.control.reasons import Kind, Reason, Then, _TEXT, reason
from can_seeker.control.safety_filter import SafetyFilter
from can_seeker.params import defaults

CONFIG = controller_settings(defaults(PARAMS))


def safety_with_wall_at(x_m):
    navigator = Navigator(0.1, 10.0, CONFIG.robot_radius, CONFIG.plan_margin,
                          CONFIG.safety_margin, CONFIG.obstacle_memory,
                          CONFIG.unknown_floor_wait)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    angles = np.radians(np.arange(-180.0, 180.0, 1.0))
    ranges = np.where(np.abs(np.cos(angles)) > 0.5, 1.5, 1.5)
    ranges = np.where(np.cos(angles) > 0.5, x_m / np.cos(angles), ranges)
    ends = np.stack((ranges * np.cos(angles), ranges * np.sin(angles)), axis=-1)
    navigator.add_scan(ends, np.cos(angles) > 0.5, (0.0, 0.0), navigator.pose, 0.0, 0.0, 'scan')
    return SafetyFilter(CONFIG, navigator, True)


def test_an_obstacle_ahead_caps_the_speed_and_says_so():
    safety = safety_with_wall_at(0.4)
    (linear, angular), why = safety.filter((0.4, 0.2), [], None)
    assert 0.0 <= linear < 0.4 and angular == 0.2
    assert why.kind is Kind.SPEED_CAPPED and why['ahead'] and not why['unknown_floor']
    assert why['speed'] == linear and why['then'] is Then.WAIT


def test_turning_in_place_and_a_free_way_pass_unchanged():
    safety = safety_with_wall_at(0.4)
    assert safety.filter((0.0, 1.2), [], None) == ((0.0, 1.2), None)
    assert safety.filter((-0.05, 0.0), [], None) == ((-0.05, 0.0), None)


def test_stale_sensing_allows_turning_only():
    safety = safety_with_wall_at(2.0)
    (linear, angular), why = safety.filter((0.3, -0.4), [MissingInput('scan', 'no scan yet')],
                                           None)
    assert (linear, angular) == (0.0, -0.4)
    assert why.kind is Kind.SENSING_STALE and why['problems'] == 'no scan yet'


def test_the_filter_is_stateless():
    safety = safety_with_wall_at(0.4)
    first = safety.filter((0.4, 0.0), [], None)
    safety.filter((0.1, 0.0), [], None)
    assert safety.filter((0.4, 0.0), [], None) == first


def test_without_obstacle_sensing_nothing_is_capped():
    safety = safety_with_wall_at(0.2)
    safety.senses_obstacles = False
    assert safety.filter((0.4, 0.0), [MissingInput('scan', 'x')], None) == ((0.4, 0.0), None)


def test_every_reason_kind_has_its_text():
    assert set(_TEXT) == set(Kind)
    assert reason(Kind.TOO_CLOSE, gap_m=0.2).text == \
        'closer than stop_distance (gap 0.200 m): no driving forward'
    assert isinstance(reason(Kind.STOPPED_AT_CAN), Reason)
    assert math.isclose(reason(Kind.DEADBAND, gap_error_m=-0.002, bearing_rad=0.0)
                        ['gap_error_m'], -0.002)
