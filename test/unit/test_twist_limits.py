"""Speed and acceleration limits of a (linear, angular) command."""
import math

import pytest

from can_seeker.control.twist_limits import TwistLimits, clamp, limit_twist, step_toward

LIMITS = TwistLimits(max_forward=0.4, max_reverse=0.1, max_angular=1.0, linear_accel=0.5,
                     angular_accel=2.0)


def test_step_toward_stops_at_target():
    assert step_toward(0.0, 0.05, 0.1) == 0.05
    assert step_toward(0.0, 1.0, 0.1) == pytest.approx(0.1)
    assert step_toward(0.3, -1.0, 0.1) == pytest.approx(0.2)


def test_speeds_are_clipped_to_limits_after_enough_time():
    assert limit_twist((0.0, 0.0), (2.0, -5.0), 10.0, LIMITS) == (0.4, -1.0)
    assert limit_twist((0.0, 0.0), (-2.0, 5.0), 10.0, LIMITS) == (-0.1, 1.0)


def test_acceleration_limits_each_axis():
    linear, angular = limit_twist((0.0, 0.0), (0.4, 1.0), 0.05, LIMITS)
    assert linear == pytest.approx(0.025)
    assert angular == pytest.approx(0.1)


def test_deceleration_is_limited_too():
    linear, angular = limit_twist((0.4, -1.0), (0.0, 0.0), 0.1, LIMITS)
    assert linear == pytest.approx(0.35)
    assert angular == pytest.approx(-0.8)


def test_reaches_exact_zero():
    assert limit_twist((0.01, 0.02), (0.0, 0.0), 0.05, LIMITS) == (0.0, 0.0)


@pytest.mark.parametrize('dt_s', [-0.5, math.nan, math.inf])
def test_clock_jumps_allow_no_change(dt_s):
    assert limit_twist((0.2, 0.3), (0.0, 0.0), dt_s, LIMITS) == (0.2, 0.3)


@pytest.mark.parametrize('previous,desired', [
    ((0.0, 0.0), (math.nan, math.nan)), ((0.0, 0.0), (0.2, math.nan)),
    ((0.3, 0.5), (math.nan, 0.0)), ((0.0, 0.0), (math.inf, 0.0)), ((math.nan, 0.0), (0.2, 0.0)),
])
def test_a_non_finite_value_gives_zero_never_a_limit(previous, desired):
    assert limit_twist(previous, desired, 0.05, LIMITS) == (0.0, 0.0)


def test_non_finite_limits_give_zero():
    limits = TwistLimits(math.nan, 0.1, 1.0, 0.5, 2.0)
    assert limit_twist((0.0, 0.0), (0.2, 0.5), 0.05, limits) == (0.0, 0.0)


def test_clamp_refuses_nan():
    with pytest.raises(ValueError):
        clamp(math.nan, -1.0, 1.0)
    assert clamp(math.inf, -1.0, 1.0) == 1.0
