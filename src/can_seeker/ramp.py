"""Bounded steps of a value: shared by the controller's twist limits and the simulated base's
acceleration limits (neither imports the other)."""
import math


def clamp(value: float, low: float, high: float) -> float:
    """``value`` limited to [low, high]; ValueError for a NaN, which has no place in it."""
    if math.isnan(value) or math.isnan(low) or math.isnan(high):
        raise ValueError('cannot clamp %r to [%r, %r]' % (value, low, high))
    return max(low, min(high, value))


def step_toward(current: float, target: float, max_step: float) -> float:
    """Move from ``current`` toward ``target`` by at most ``max_step``."""
    return current + clamp(target - current, -max_step, max_step)
