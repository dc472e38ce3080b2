"""Stale-command braking, acceleration limits and differential-drive wheel speeds."""
import math

import pytest

from can_seeker.sim.drive import CommandWatchdog, TwistLimiter, wheel_speeds


def test_watchdog_holds_a_fresh_command_and_zeroes_a_stale_one():
    watchdog = CommandWatchdog(0.5)
    assert watchdog.target(0.0) == (0.0, 0.0)
    watchdog.command(0.2, -1.0, now_s=10.0)
    assert watchdog.target(10.0) == (0.2, -1.0)
    assert watchdog.target(10.5) == (0.2, -1.0)
    assert watchdog.target(10.51) == (0.0, 0.0)


def test_watchdog_reset_forgets_the_command():
    watchdog = CommandWatchdog(0.5)
    watchdog.command(0.3, 0.0, now_s=1.0)
    watchdog.reset()
    assert watchdog.target(1.0) == (0.0, 0.0)


def test_limiter_ramps_at_the_acceleration_limits():
    limiter = TwistLimiter(1.0, 4.0)
    dt_s = 0.01
    twist = limiter.step(0.2, -1.0, dt_s)
    assert twist == pytest.approx((0.01, -0.04))
    for _ in range(9):
        twist = limiter.step(0.2, -1.0, dt_s)
    assert twist == pytest.approx((0.1, -0.4))
    for _ in range(30):
        twist = limiter.step(0.2, -1.0, dt_s)
    assert twist == pytest.approx((0.2, -1.0))


def test_limiter_brakes_to_exactly_zero():
    limiter = TwistLimiter(1.0, 4.0)
    for _ in range(100):
        limiter.step(0.25, 0.5, 0.01)
    for _ in range(24):
        limiter.step(0.0, 0.0, 0.01)
    assert limiter.linear_mps > 0.0
    assert limiter.step(0.0, 0.0, 0.01) == (0.0, 0.0)


def test_ramp_distance_lost_equals_braking_distance_gained():
    """Commanding v for T seconds then zero moves v * T: what the ramp-up loses, braking adds."""
    limiter = TwistLimiter(1.0, 4.0)
    dt_s, distance_m = 1.0 / 240.0, 0.0
    for step in range(int(3.0 / dt_s)):
        linear_mps, _ = limiter.step(0.2 if step < 480 else 0.0, 0.0, dt_s)
        distance_m += linear_mps * dt_s
    assert distance_m == pytest.approx(0.4, rel=0.005)


def test_limiter_reset_stops_at_once():
    limiter = TwistLimiter(1.0, 4.0)
    limiter.step(1.0, 1.0, 1.0)
    limiter.reset()
    assert (limiter.linear_mps, limiter.angular_radps) == (0.0, 0.0)


def test_wheel_speeds_of_straight_and_turning_motion():
    assert wheel_speeds(0.36, 0.0, 0.235, 0.036) == pytest.approx((10.0, 10.0))
    left, right = wheel_speeds(0.0, 1.0, 0.235, 0.036)
    assert right == pytest.approx(0.1175 / 0.036)
    assert left == pytest.approx(-right)
    left, right = wheel_speeds(0.2, 0.5, 0.235, 0.036)
    assert (right - left) * 0.036 / 0.235 == pytest.approx(0.5)
    assert (right + left) * 0.036 / 2.0 == pytest.approx(0.2)
    assert all(math.isfinite(speed) for speed in (left, right))
