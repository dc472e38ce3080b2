"""Time between two stamps, the same in every run of a lockstep trial.

Stamps are whole nanoseconds rounded from the simulator's time, so one frame period comes out a
nanosecond longer or shorter depending on the absolute sim time a trial started at (the time
its harness took to start it). Differences are taken to whole microseconds, so a timer that
ends after exactly fifteen frames, or an acceleration ramp's step, is the same in every run.
"""

DECIMALS = 6
"""Time differences are rounded to this many decimals of a second (microseconds)."""


def elapsed_s(later_s: float, earlier_s: float) -> float:
    """``later_s - earlier_s`` (s) to the microsecond."""
    return round(later_s - earlier_s, DECIMALS)
