"""EXPLORE: head for the nearest place an all-round scan showed a small object standing free
that the camera has not had in view (the can, maybe), else for the best floor not covered yet;
SEARCH again on arrival (a place where the can may stand then counts as looked at: on the way a
can there would have come into view)."""
from typing import Optional

import numpy as np

from can_seeker.control.behaviours.base import Behaviour, Result
from can_seeker.control.path_planner import GOAL_REACHED_M
from can_seeker.control.reasons import Consequence, Kind, reason
from can_seeker.control.supervisor import Event

FRONTIER_MIN_UNSEEN = 6
"""A frontier goal has at least this many uncovered cells about it."""


class Explore(Behaviour):
    """Remembers its goal (odom) and whether it is a place where the can may stand."""

    def start(self, now_s: float) -> None:
        self.goal_xy: Optional[np.ndarray] = None
        self.goal_is_candidate = False

    @property
    def candidate_goal(self) -> Optional[np.ndarray]:
        """The goal when it is a place where the can may stand, else None."""
        return self.goal_xy if self.goal_is_candidate else None

    def give_up_goal(self) -> None:
        """Never head for the goal again (choose another)."""
        if self.goal_xy is not None:
            self.context.navigator.world.give_up_at(self.goal_xy)
        self.goal_xy = None

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        return Event.CAN_RANGED if ranged else None

    def command(self, now_s: float) -> Result:
        context, config = self.context, self.config
        navigator = context.navigator
        if not context.can_navigate(now_s):
            context.because(context.cannot_navigate(now_s, Consequence.NO_EXPLORING))
            return Result((0.0, 0.0))
        covered = (self.goal_xy is not None
                   and (navigator.world.candidates.is_viewed(self.goal_xy) if self.goal_is_candidate
                        else navigator.world.is_seen(self.goal_xy)))
        if self.goal_xy is None or covered or context.paths.replan_due(now_s):
            previous_goal, previous_is_candidate = self.goal_xy, self.goal_is_candidate
            self.goal_xy = navigator.unviewed_candidate()
            self.goal_is_candidate = self.goal_xy is not None
            if self.goal_xy is None:
                self.goal_xy = navigator.frontier(
                    config.explore_turn_cost, FRONTIER_MIN_UNSEEN,
                    None if previous_goal is None or previous_is_candidate else previous_goal)
            if (self.goal_xy is None or previous_goal is None
                    or not np.array_equal(self.goal_xy, previous_goal)):
                context.paths.clear()
            if self.goal_xy is None:
                navigator.world.forget_coverage()
                return Result(context.turning(), Event.NOTHING_TO_EXPLORE)
        if navigator.distance_to(self.goal_xy) < GOAL_REACHED_M:
            if self.goal_is_candidate:
                navigator.world.give_up_at(self.goal_xy)
            return Result(context.turning(), Event.GOAL_REACHED)
        command = context.paths.follow(self.goal_xy, now_s, context.because,
                                       self.candidate_goal)
        if command is None:
            navigator.world.give_up_at(self.goal_xy)
            self.goal_xy = None
            context.because(reason(Kind.NO_PATH_TO_GOAL))
            return Result((0.0, 0.0))
        return Result(command)
