"""Bump recovery: what the robot does when its bumper reports a touch.

A touch means the sensors missed something the robot drove into (a wall coloured like the
floor, glass, a chair leg thinner than a camera scan's resolution). The recovery stops the
robot at once, marks where it touched (the robot's front on its heading: a bumper reports no
side) as an obstacle that stays in the map, backs off ``BACK_OFF_M`` at ``BACK_OFF_MPS`` and
then hands back to the behaviour that was running, which now plans and drives around the
contact. Pure: the controller feeds it the bumper and the pose, and asks it for a command.
"""
import math
from typing import Optional, Tuple

from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.navigation import Pose2D
from can_seeker.control.reasons import Kind, Reason, reason

BACK_OFF_M = 0.1
"""How far the robot backs off after a bump (m): far enough for a bumper's travel (a few cm)
to spring back and for a turn in place to free the body (a robot pressed against a wall
scrapes it while it turns), short enough to stay on floor it just drove over."""
BACK_OFF_MPS = 0.05
"""Backing-off speed (m/s; at most ~max_reverse, none with a ~max_reverse of 0): slow, as
nothing looks behind the robot but the map of the floor it came over."""
BACK_OFF_GRACE_S = 3.0
"""The back-off gives up this long after it should have covered ``BACK_OFF_M`` (s): the
safety layer or a stuck wheel keeps the robot where it is, and the behaviour takes over."""


class BumpRecovery:
    """Stop, mark the contact, back off, hand back (see the module's docstring)."""

    def __init__(self, robot_radius_m: float, max_reverse_mps: float):
        self.robot_radius_m = robot_radius_m
        self.speed_mps = min(BACK_OFF_MPS, max_reverse_mps)
        self.count = 0
        self.pressed = False
        self.cancel()

    def cancel(self) -> None:
        """No recovery under way (the bump count and the bumper's state stay)."""
        self.start: Optional[Pose2D] = None
        self.start_s = 0.0

    @property
    def active(self) -> bool:
        """True from a bump until the back-off is over."""
        return self.start is not None

    def bumped(self, pressed: bool, pose: Optional[Pose2D],
               now_s: float) -> Optional[Tuple[float, float]]:
        """A bumper message at ``now_s`` with the robot at ``pose`` (odom; None: unknown).
        Returns the odom point of the contact (the robot's front on its heading) when this
        message is a new touch (a press after a release) and the pose is known, else None. A
        new touch with a known pose starts the recovery afresh."""
        new_touch = pressed and not self.pressed
        self.pressed = pressed
        if not new_touch:
            return None
        self.count += 1
        if pose is None:
            return None
        self.start, self.start_s = pose, now_s
        return (pose.x + self.robot_radius_m * math.cos(pose.yaw),
                pose.y + self.robot_radius_m * math.sin(pose.yaw))

    def command(self, pose: Optional[Pose2D],
                now_s: float) -> Optional[Tuple[Tuple[float, float], Reason]]:
        """((linear m/s, angular rad/s), why) while the recovery runs, None once it is over:
        straight back until ``BACK_OFF_M`` from where the bump was, or until its time is
        up."""
        if self.start is None or pose is None:
            return None
        if self.speed_mps <= 0.0:
            self.cancel()
            return None
        backed_m = math.hypot(pose.x - self.start.x, pose.y - self.start.y)
        limit_s = BACK_OFF_M / self.speed_mps + BACK_OFF_GRACE_S
        if backed_m >= BACK_OFF_M or elapsed_s(now_s, self.start_s) > limit_s:
            self.cancel()
            return None
        return (-self.speed_mps, 0.0), reason(Kind.BUMPED, backed_m=backed_m,
                                              back_off_m=BACK_OFF_M)
