"""Velocity and acceleration limits for a planar (linear, angular) velocity command.

Kept apart from the controller's state machine so the same limits apply whatever the state
asks for, and so they can be tested on their own. Every comparison with NaN is false, so
min/max would turn a NaN into a limit: a non-finite value is refused (ValueError) or yields
zero, never a speed.
"""
import math
from dataclasses import astuple, dataclass
from typing import Sequence, Tuple

from can_seeker.ramp import clamp, step_toward  # noqa: F401 (the controller's API too)

Command = Tuple[float, float]
"""(linear m/s, angular rad/s) in base_link."""
ZERO: Command = (0.0, 0.0)


@dataclass(frozen=True)
class TwistLimits:
    """Bounds on a differential-drive command.

    ``max_forward`` and ``max_reverse`` bound the linear speed (m/s, both positive),
    ``max_angular`` the turn rate (rad/s), ``linear_accel`` and ``angular_accel`` how fast each
    may change (m/s^2, rad/s^2).
    """

    max_forward: float
    max_reverse: float
    max_angular: float
    linear_accel: float
    angular_accel: float


def require_finite(command: Tuple[float, float], what: str = 'command') -> Tuple[float, float]:
    """``command`` unchanged; ValueError naming ``what`` when a part of it is not finite."""
    if not all_finite(command):
        raise ValueError('%s %r is not finite' % (what, tuple(command)))
    return command


def all_finite(values: Sequence[float]) -> bool:
    """True when no value is NaN or infinite."""
    return all(math.isfinite(value) for value in values)


def limit_twist(previous: Tuple[float, float], desired: Tuple[float, float], dt_s: float,
                limits: TwistLimits) -> Tuple[float, float]:
    """The (linear m/s, angular rad/s) command to send ``dt_s`` after ``previous`` was sent.

    ``desired`` is first clipped to the speed limits, then approached no faster than the
    acceleration limits allow. A negative or non-finite ``dt_s`` (a clock that jumped) permits
    no change at all rather than an unbounded one. A non-finite command or limit gives zero.
    """
    if not all_finite(tuple(previous) + tuple(desired) + astuple(limits)):
        return ZERO
    if not math.isfinite(dt_s) or dt_s < 0.0:
        dt_s = 0.0
    linear = clamp(desired[0], -limits.max_reverse, limits.max_forward)
    angular = clamp(desired[1], -limits.max_angular, limits.max_angular)
    return (step_toward(previous[0], linear, limits.linear_accel * dt_s),
            step_toward(previous[1], angular, limits.angular_accel * dt_s))
