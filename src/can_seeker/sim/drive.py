"""Differential-drive command handling: stale-command braking, acceleration limits, wheel speeds.

A robot must not keep executing the last command after its publisher died, and a velocity step
makes the wheels slip; so the executed twist is the commanded one while it is fresh (zero once it
is older than the timeout), approached at bounded accelerations.
"""
import math
from typing import Tuple

from can_seeker.ramp import step_toward


class CommandWatchdog:
    """Holds the latest (linear m/s, angular rad/s) command and zeroes it after ``timeout_s``."""

    def __init__(self, timeout_s: float):
        self.timeout_s = timeout_s
        self.reset()

    def reset(self):
        """Forget the current command: the target is zero until the next one."""
        self._command = (0.0, 0.0)
        self._received_s = -math.inf

    def command(self, linear_mps: float, angular_radps: float, now_s: float):
        """Record a command received at ``now_s`` (s)."""
        self._command = (float(linear_mps), float(angular_radps))
        self._received_s = now_s

    def target(self, now_s: float) -> Tuple[float, float]:
        """The twist to drive at ``now_s``: the command while fresh, zero once it is stale."""
        if now_s - self._received_s > self.timeout_s:
            return 0.0, 0.0
        return self._command


class TwistLimiter:
    """Moves the executed twist toward the target at bounded accelerations so the wheels grip."""

    def __init__(self, max_linear_accel_mps2: float, max_angular_accel_radps2: float):
        self.max_linear_accel_mps2 = max_linear_accel_mps2
        self.max_angular_accel_radps2 = max_angular_accel_radps2
        self.reset()

    def reset(self):
        """Back to standstill."""
        self.linear_mps = 0.0
        self.angular_radps = 0.0

    def step(self, target_linear_mps: float, target_angular_radps: float,
             dt_s: float) -> Tuple[float, float]:
        """Advance by ``dt_s`` toward the target twist; returns the twist to execute now."""
        self.linear_mps = step_toward(self.linear_mps, target_linear_mps,
                                      self.max_linear_accel_mps2 * dt_s)
        self.angular_radps = step_toward(self.angular_radps, target_angular_radps,
                                         self.max_angular_accel_radps2 * dt_s)
        return self.linear_mps, self.angular_radps


def wheel_speeds(linear_mps: float, angular_radps: float, wheel_separation_m: float,
                 wheel_radius_m: float) -> Tuple[float, float]:
    """(left, right) wheel angular speeds (rad/s) that drive the base at the given twist."""
    half_track_mps = angular_radps * wheel_separation_m / 2.0
    return ((linear_mps - half_track_mps) / wheel_radius_m,
            (linear_mps + half_track_mps) / wheel_radius_m)
