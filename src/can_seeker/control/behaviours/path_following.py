"""Driving along grid paths, shared by EXPLORE, APPROACH and LOST: the path and when it was
planned (a goal's path is planned again every ``REPLAN_PERIOD_S``)."""
import math
from typing import Optional, Tuple

import numpy as np

from can_seeker.control.elapsed import elapsed_s


class PathFollower:
    """The current path (``path_xy``, odom; None: none) and its planning time."""

    def __init__(self, config, navigator):
        self.config = config
        self.navigator = navigator
        self.reset()

    def reset(self) -> None:
        """No path, never planned."""
        self.path_xy: Optional[np.ndarray] = None
        self.planned_s = -math.inf

    def clear(self) -> None:
        """Drop the path (the next :meth:`follow` plans one)."""
        self.path_xy = None

    def replan_due(self, now_s: float) -> bool:
        """True when ``REPLAN_PERIOD_S`` has passed since the last planning."""
        return elapsed_s(now_s, self.planned_s) >= self.config.replan_period

    def follow(self, goal_xy, now_s: float, because,
               exclude_xy=None) -> Optional[Tuple[float, float]]:
        """The command along a grid path to ``goal_xy`` (``exclude_xy``: the can, no
        obstacle), or None when no path reaches it; ``because`` hears why it only turns."""
        config = self.config
        if self.path_xy is None or self.replan_due(now_s):
            self.path_xy = self.navigator.path_to(goal_xy, exclude_xy,
                                                  config.can_exclusion_radius, self.path_xy)
            self.planned_s = now_s
        if self.path_xy is None:
            return None
        command, why = self.navigator.follow(self.path_xy, config.explore_linear,
                                             math.radians(config.turn_in_place_deg),
                                             config.angular_gain)
        because(why)
        return command
