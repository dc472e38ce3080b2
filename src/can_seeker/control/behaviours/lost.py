"""LOST: back toward where the can was seen last (a grid path), facing it once within reach,
else turning toward the side it left; SEARCH once LOST_TIMEOUT_S passed without getting nearer
that place, or at once when facing its place shows it is not there."""
import math
from typing import Optional

import numpy as np

from can_seeker.control import avoidance
from can_seeker.control.behaviours.base import Behaviour, Result
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.path_planner import GOAL_REACHED_M
from can_seeker.control.reasons import Consequence, Kind, reason
from can_seeker.control.supervisor import Event

NOT_THERE_S = 1.0
"""LOST within reach of where the can was seen last, facing it (within
REAPPROACH_BEARING_DEG, its base in view) without seeing it for this long (s): it is not
there (moved, or a misplaced sighting put it there), so SEARCH at once instead of standing
until LOST_TIMEOUT_S."""

PROGRESS_M = 0.1
"""LOST keeps heading for the can's last place while each LOST_TIMEOUT_S brings the robot at
least this much nearer to it than it has been (m): a long way round an obstacle is no reason to
give the can up, standing or circling is. Exploration would not bring the robot back: the floor
about a can it saw counts as covered."""


class Lost(Behaviour):
    """Remembers since when it last got nearer the can's last place (and how near), and since
    when it faces that place."""

    def start(self, now_s: float) -> None:
        self.nearer_since_s = now_s
        self.nearest_m: Optional[float] = None
        self.facing_since_s: Optional[float] = None

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        return Event.CAN_RANGED if ranged else None

    def expired(self, now_s: float) -> Optional[Event]:
        can_xy = self.context.tracker.can_xy
        if can_xy is not None:
            pose = self.context.navigator.pose
            distance_m = math.hypot(can_xy[0] - pose.x, can_xy[1] - pose.y)
            if self.nearest_m is None or distance_m < self.nearest_m - PROGRESS_M:
                self.nearest_m = distance_m
                self.nearer_since_s = now_s
        if elapsed_s(now_s, self.nearer_since_s) > self.config.lost_timeout:
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
