"""Stall watchdogs, after each command: :class:`GiveUpGoal` (EXPLORE) and :class:`KeepToPath`
(APPROACH and LOST)."""
import math
from typing import Optional, Tuple

import numpy as np

from can_seeker.control.behaviours.approach import DIRECT_GAP_M
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.reasons import Kind, reason
from can_seeker.control.supervisor import State

STALL_CELLS = 5
STALL_APPROACH_M = 0.2
STALL_S = 6.0
APPROACH_STALL_BEYOND_MEMORY_S = 5.0
"""APPROACH and LOST that have brought the robot no ``STALL_APPROACH_M`` nearer to the can,
farther than ``DIRECT_GAP_M`` from it, for this much longer than ``OBSTACLE_MEMORY_S`` (s)
change how they head for it (:class:`KeepToPath`): a robot held back by an obstacle it no
longer sees (a phantom too) first gets the time to forget it."""


class GiveUpGoal:
    """EXPLORE gives up its goal when in ``STALL_S`` the camera has covered fewer than
    ``STALL_CELLS`` new cells and, on the way to a place where the can may stand (which lies
    across floor already covered), the robot has not come ``STALL_APPROACH_M`` nearer to it:
    the goal cannot be seen from where the robot can go, or the safety layer keeps it from
    getting there. Such a place chosen after floor, or after a place now looked at, has its own
    ``STALL_S`` (not when the robot switches between two places it has not looked at yet,
    which would never run out)."""

    def __init__(self, navigator, explore):
        self.navigator = navigator
        self.explore = explore
        self.reset()

    def reset(self, _state=None) -> None:
        self.progress: Optional[Tuple[int, float, float, Optional[np.ndarray]]] = None

    def after_tick(self, state: State, now_s: float, because) -> None:
        if state is not State.EXPLORE:
            self.progress = None
            return
        navigator = self.navigator
        covered = navigator.world.covered_count()
        candidate = self.explore.candidate_goal
        distance = math.inf if candidate is None else navigator.distance_to(candidate)
        if (self.progress is not None and candidate is not None
                and not np.array_equal(candidate, self.progress[3])):
            previous = self.progress[3]
            fresh = previous is None or navigator.world.candidates.is_viewed(previous)
            self.progress = (self.progress[0], now_s if fresh else self.progress[1], distance,
                             candidate)
        if (self.progress is None or covered >= self.progress[0] + STALL_CELLS
                or (candidate is not None and distance <= self.progress[2] - STALL_APPROACH_M)):
            self.progress = (covered, now_s, distance, candidate)
        elif elapsed_s(now_s, self.progress[1]) > STALL_S:
            self.explore.give_up_goal()
            self.progress = (covered, now_s, math.inf, None)


class KeepToPath:
    """APPROACH and LOST switch between their usual way to the can (the direct law while the
    straight line is clear, else a grid path; LOST when the can leaves the view) and keeping to
    the grid path (``active``: the can leaving the view is no reason to stop following it)
    whenever in ``OBSTACLE_MEMORY_S`` + ``APPROACH_STALL_BEYOND_MEMORY_S`` they have brought the
    robot no ``STALL_APPROACH_M`` nearer to it while it is farther than ``DIRECT_GAP_M``. A way
    that ends in a cycle (an obstacle's corner beside the straight line: the path around it
    turns the camera away from the can, LOST turns back, the direct law meets the corner again)
    or in standing gives way to the other. Its memory spans APPROACH and LOST."""

    def __init__(self, config, navigator, tracker, paths):
        self.config = config
        self.navigator = navigator
        self.tracker = tracker
        self.paths = paths
        self.progress: Optional[Tuple[float, float]] = None
        self.active = False

    def reset(self, state: Optional[State] = None) -> None:
        """Entering ``state``: outside APPROACH and LOST the memory starts afresh."""
        if state not in (State.APPROACH, State.LOST):
            self.progress = None
            self.active = False

    def keeping(self) -> bool:
        """True while it keeps to a path and the can is farther than ``DIRECT_GAP_M``."""
        return (self.active and self.tracker.can_xy is not None
                and self.navigator.pose is not None
                and self.tracker.gap_to_last_m() > DIRECT_GAP_M)

    def after_tick(self, state: State, now_s: float, because) -> None:
        tracker = self.tracker
        if (state not in (State.APPROACH, State.LOST) or tracker.can_xy is None
                or self.navigator.pose is None):
            return
        distance = self.navigator.distance_to(tracker.can_xy)
        stall_s = self.config.obstacle_memory + APPROACH_STALL_BEYOND_MEMORY_S
        if (self.progress is None or distance <= self.progress[0] - STALL_APPROACH_M
                or not tracker.gap_to_last_m() > DIRECT_GAP_M):
            self.progress = (distance, now_s)
        elif elapsed_s(now_s, self.progress[1]) > stall_s:
            self.active = not self.active
            self.progress = (distance, now_s)
            self.paths.clear()
            because(reason(Kind.APPROACH_STALLED, nearer_m=STALL_APPROACH_M, stall_s=stall_s,
                           keep_to_path=self.active))
