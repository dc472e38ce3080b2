"""Recoveries for a robot the safety filter keeps from driving forward because of unknown floor,
tried in order: :class:`BackUpToSeeFloor` where that floor lies below the camera's view (no
turn in place brings it into view), else :class:`TurnToLook` toward it."""
import math
from typing import Optional, Tuple

from can_seeker.control.reasons import Kind, Reason, Then, reason
from can_seeker.control.safety_filter import Verdict
from can_seeker.control.twist_limits import Command

BACK_UP_BEYOND_M = 0.05
"""A robot backing up to see floor below the camera's view backs up this much farther than
that floor is below it, so the image's bottom rows see it whole."""
LOOK_BELOW_FRACTION = 0.5
"""A robot kept from driving by unknown floor and turning slower than this fraction of
SEARCH_ANGULAR_RADPS turns to look at that floor instead."""


class BackUpToSeeFloor:
    """Backs up at ~max_reverse until the unknown floor is in view; remembers where it started
    and how far it must go (per state: a state change ends it)."""

    def __init__(self, config, navigator, safety, camera_view):
        self.config = config
        self.navigator = navigator
        self.safety = safety
        self.camera_view = camera_view
        self.reset()

    def reset(self, _state=None) -> None:
        """Not backing up."""
        self.backing: Optional[Tuple[float, float, float]] = None

    def resume(self, exclude_xy) -> Optional[Tuple[Command, Reason]]:
        """The back-up under way, with why, until it has gone far enough or may not go on."""
        if self.backing is None:
            return None
        backed_m = self.navigator.distance_to(self.backing[:2])
        if backed_m < self.backing[2] and self.safety.can_back_up(exclude_xy):
            return ((-self.config.max_reverse, 0.0),
                    reason(Kind.BACKING_TO_SEE, backed_m=backed_m, total_m=self.backing[2]))
        self.backing = None
        return None

    def unblock(self, command: Command, verdict: Verdict,
                exclude_xy) -> Optional[Tuple[Command, Then]]:
        """Start backing up when the blocking floor lies below the camera's view."""
        hidden_m = self._below_view_m(verdict.unknown_point)
        if hidden_m > 0.0 and self.safety.can_back_up(exclude_xy):
            pose = self.navigator.pose
            self.backing = (pose.x, pose.y, hidden_m + BACK_UP_BEYOND_M)
            return (-self.config.max_reverse, 0.0), Then.BACK_UP
        return None

    def _below_view_m(self, point_base) -> float:
        """How far (m) the robot must back up for floor point ``point_base`` (base_link) to
        come half a grid cell inside the image's floor (0 when it is in view, no backing up
        brings it there or the view is not known): beside the robot's front, below the narrow
        bottom of a steep camera's view, that is farther than below its middle."""
        view = self.camera_view()
        if view is None or view.base_near_m <= 0.0:
            return 0.0
        back_m = view.back_up_to_see_m(point_base, self.navigator.world.resolution_m / 2.0)
        return back_m if math.isfinite(back_m) else 0.0


class TurnToLook:
    """Turns toward the unknown floor at SEARCH_ANGULAR_RADPS, unless turning already."""

    def __init__(self, config):
        self.config = config

    def unblock(self, command: Command, verdict: Verdict,
                exclude_xy) -> Optional[Tuple[Command, Then]]:
        search_angular = self.config.search_angular
        if abs(command[1]) >= LOOK_BELOW_FRACTION * search_angular:
            return None
        side = verdict.unknown_point[1] or 1.0
        return (verdict.linear, math.copysign(search_angular, side)), Then.LOOK
