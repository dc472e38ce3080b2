"""WANDER (``~behaviour`` wander, no can): straight on while the way ahead is clear, else turn
away in place."""
import math

from can_seeker.control import avoidance
from can_seeker.control.behaviours.base import Behaviour, Result


class Wander(Behaviour):
    """Remembers the side it turns to."""

    def start(self, now_s: float) -> None:
        self.turn_sign = 1.0

    def command(self, now_s: float) -> Result:
        config = self.config
        points, clearance = self.context.navigator.obstacles_base()
        ahead_m = avoidance.free_travel_m(points, config.explore_linear, 0.0, clearance,
                                          config.wander_clearance)
        if ahead_m >= config.wander_clearance:
            return Result((config.explore_linear, 0.0))
        last_angular = self.context.last_command[1]
        if last_angular != 0.0:
            return Result((0.0, math.copysign(config.search_angular, last_angular)))
        self.turn_sign = avoidance.open_turn_sign(points, self.turn_sign)
        return Result((0.0, self.turn_sign * config.search_angular))
