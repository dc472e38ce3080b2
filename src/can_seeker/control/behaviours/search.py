"""SEARCH: turn in place toward the side the can was seen last, counting the turn."""
import math
from typing import Optional

from can_seeker.control import avoidance
from can_seeker.control.behaviours.base import Behaviour, Result
from can_seeker.control.reasons import Consequence, Kind, reason
from can_seeker.control.supervisor import Event


class Search(Behaviour):
    """Turns at SEARCH_ANGULAR_RADPS; after a full turn it explores (unless ~explore is false or
    grid paths are out of reach: then it turns on)."""

    def start(self, now_s: float) -> None:
        self.searched_rad = 0.0

    def on_pose(self, previous, pose) -> None:
        self.searched_rad += abs(avoidance.wrap_angle(pose.yaw - previous.yaw))

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        return Event.CAN_RANGED if ranged else None

    def command(self, now_s: float) -> Result:
        context = self.context
        if self.searched_rad < 2.0 * math.pi:
            return Result(context.turning())
        if not self.config.explore:
            context.because(reason(Kind.EXPLORE_OFF))
            return Result(context.turning())
        if not context.can_navigate(now_s):
            context.because(context.cannot_navigate(now_s, Consequence.SEARCH_ON))
            return Result(context.turning())
        return Result(None, Event.SEARCHED_ALL_ROUND)
