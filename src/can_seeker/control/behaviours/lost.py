"""LOST: back toward where the can was seen last (a grid path), facing it once within reach,
else turning toward the side it left; SEARCH after LOST_TIMEOUT_S, or at once when facing its
place shows it is not there."""
import math
from typing import Optional

import numpy as np

from can_seeker.control import avoidance
from can_seeker.control.behaviours.base import Behaviour, Result
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.navigation import GOAL_REACHED_M
from can_seeker.control.reasons import Consequence, Kind, reason
from can_seeker.control.supervisor import Event

NOT_THERE_S = 1.0
"""LOST within reach of where the can was seen last, facing it (within
REAPPROACH_BEARING_DEG, its base in view) without seeing it for this long (s): it is not
there (moved, or a misplaced sighting put it there), so SEARCH at once instead of standing
until LOST_TIMEOUT_S."""


class Lost(Behaviour):
    """Remembers since when it is LOST and since when it faces the can's last place."""

    def start(self, now_s: float) -> None:
        self.lost_since_s = now_s
        self.facing_since_s: Optional[float] = None

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        return Event.CAN_RANGED if ranged else None

    def expired(self, now_s: float) -> Optional[Event]:
        if elapsed_s(now_s, self.lost_since_s) > self.config.lost_timeout:
            return Event.LOST_TIMEOUT
        return None

    def command(self, now_s: float) -> Result:
        context, config = self.context, self.config
        tracker = context.tracker
        turning = context.turning()
        if tracker.can_xy is None or not context.can_navigate(now_s):
            context.because(context.cannot_navigate(now_s, Consequence.TURN_TO_LAST_SEEN))
            return Result(turning)
        pose = context.navigator.pose
        can_base = avoidance.to_frame(np.array(tracker.can_xy), pose.x, pose.y, pose.yaw)[0]
        reach_m = config.robot_radius + config.can_radius + config.stop_distance
        if np.hypot(*can_base) < reach_m + GOAL_REACHED_M:
            facing = (abs(math.atan2(can_base[1], can_base[0]))
                      <= math.radians(config.reapproach_bearing_deg)
                      and not tracker.below_view(context.camera_view))
            if not facing:
                self.facing_since_s = None
            elif self.facing_since_s is None:
                self.facing_since_s = now_s
            elif elapsed_s(now_s, self.facing_since_s) >= NOT_THERE_S:
                context.because(reason(Kind.CAN_NOT_THERE))
                return Result(turning, Event.CAN_NOT_THERE)
            context.because(reason(Kind.TURNING_TO_LAST_SEEN if not facing
                                   else Kind.FACING_LAST_SEEN))
            return Result(avoidance.steer_to_point(can_base, 0.0, 1.0, config.angular_gain))
        command = context.paths.follow(tracker.can_xy, now_s, context.because, tracker.can_xy)
        return Result(turning if command is None else command)
