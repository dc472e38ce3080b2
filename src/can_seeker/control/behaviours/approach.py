"""APPROACH: the direct law to the can, or a grid path around obstacles while the straight line
to it crosses obstacles grown by the robot's radius and safety margin (never in the last
``DIRECT_GAP_M``, where the direct law stops in front of the can, or beside the straight line
when an obstacle holds that back: :mod:`~can_seeker.control.behaviours.stop_aside`). Within
``DISTANCE_TOLERANCE_M`` of the stop distance it only faces the can. After a stall it keeps to
the path whether or not the straight line is clear (the KeepToPath recovery)."""
import math
from typing import Optional

from can_seeker.control.behaviours.base import Behaviour, Result
from can_seeker.control.behaviours.stop_aside import StopAside
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.navigation import CLEAR_AHEAD_M
from can_seeker.control.reasons import Kind, Reason, reason
from can_seeker.control.supervisor import Event
from can_seeker.control.twist_limits import Command

DIRECT_GAP_M = 0.5
"""The last stretch (gap, m) the direct law drives, whatever stands beside it."""


def dead_band(error: float, band: float, gain: float, minimum: float) -> float:
    """Proportional command ``gain * error``: zero inside +-``band``, at least ``minimum``
    in magnitude outside it (so small errors are really corrected)."""
    if abs(error) <= band:
        return 0.0
    return math.copysign(max(minimum, gain * abs(error)), error)


class Approach(Behaviour):
    """Owns the stop point aside; reads the KeepToPath recovery's ``active``."""

    def __init__(self, context, keep_to_path):
        super().__init__(context)
        self.keep_to_path = keep_to_path
        self.stop_aside = StopAside(context.config, context.navigator, context.tracker)

    def start(self, now_s: float) -> None:
        self.stop_aside.reset()

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        return None if ranged else Event.CAN_OUT_OF_RANGE

    def command(self, now_s: float) -> Result:
        context, config = self.context, self.config
        tracker = context.tracker
        can_xy = tracker.can_xy
        if (can_xy is not None and context.can_navigate(now_s)
                and tracker.sighting.gap_m > DIRECT_GAP_M
                and (self.keep_to_path.active
                     or context.navigator.straight_line_blocked(can_xy, can_xy,
                                                                config.can_exclusion_radius)
                     or self._direct_law_held_back())):
            command = context.paths.follow(can_xy, now_s, context.because, can_xy)
            if command is not None:
                return Result(command)
            if self.keep_to_path.active and context.safety.can_back_up(can_xy):
                context.because(reason(Kind.NO_PATH_TO_CAN))
                return Result((-config.max_reverse, 0.0))
        context.paths.clear()
        aside = None
        if (can_xy is not None and context.can_navigate(now_s)
                and tracker.sighting.gap_m <= DIRECT_GAP_M
                and tracker.errors()[0] > config.distance_tolerance):
            aside = self.stop_aside.bearing()
        command = self.approach_law(aside)
        if command[0] == 0.0:
            context.because(self._standing_reason() if aside is None else
                            reason(Kind.TURNING_TO_STOP_ASIDE, bearing_rad=aside))
        return Result(command)

    def finished(self, command: Command, now_s: float) -> Optional[Event]:
        """Once within both tolerances and at rest: SETTLED where the camera ranged the can
        within VANISH_TIMEOUT_S or the can is below its view, else ARRIVED_UNSEEN: the approach
        arrived at a place a false or stale estimate put the can (one frame that ranged a
        half-hidden can far off, then carried on odometry), not at the can."""
        tracker = self.context.tracker
        gap_error, bearing = tracker.errors()
        if not (command == (0.0, 0.0) and abs(gap_error) <= self.config.distance_tolerance
                and abs(bearing) <= math.radians(self.config.bearing_tolerance_deg)):
            return None
        unseen_s = elapsed_s(now_s, tracker.ranged_s)
        if (unseen_s <= self.config.vanish_timeout
                or tracker.below_view(self.context.camera_view)):
            return Event.SETTLED
        self.context.because.state_changed(reason(Kind.ARRIVED_UNSEEN, unseen_s=unseen_s))
        return Event.ARRIVED_UNSEEN

    def approach_law(self, aim_bearing_rad: Optional[float] = None) -> Command:
        """The direct approach: steer on the bearing, speed from the gap error. While it drives
        forward it steers on ``aim_bearing_rad`` instead when given (a stop point aside); in
        the stop band it faces the can."""
        config = self.config
        gap_error, bearing = self.context.tracker.errors()
        linear = dead_band(gap_error, config.distance_tolerance / 2.0, config.linear_gain,
                           config.min_linear)
        steer = bearing if aim_bearing_rad is None or linear <= 0.0 else aim_bearing_rad
        angular = dead_band(steer, math.radians(config.bearing_tolerance_deg) / 2.0,
                            config.angular_gain, config.min_angular)
        if linear > 0.0:
            braking_speed = math.sqrt(2.0 * config.max_linear_accel * gap_error)
            heading_scale = max(0.0, 1.0 - abs(steer) / math.radians(config.turn_in_place_deg))
            linear = min(linear, braking_speed, config.max_linear) * heading_scale
        return linear, angular

    def _standing_reason(self) -> Reason:
        """Why the direct law drives neither forward nor back: the gap is in the stop band, or
        the can is too far to the side to drive yet."""
        gap_error, bearing = self.context.tracker.errors()
        if abs(gap_error) <= self.config.distance_tolerance / 2.0:
            return reason(Kind.DEADBAND, gap_error_m=gap_error, bearing_rad=bearing)
        return reason(Kind.TURNING_TO_CAN, bearing_rad=bearing,
                      turn_in_place_deg=self.config.turn_in_place_deg)

    def _direct_law_held_back(self) -> bool:
        """True when the safety layer would stop the direct law within ``CLEAR_AHEAD_M`` (an
        obstacle beside the straight line, nearer than the margin): the path follower then
        turns to a gap instead of stalling there."""
        command = self.approach_law()
        if command[0] <= 0.0:
            return False
        free_m = self.context.navigator.free_travel_m(command, self.context.tracker.can_xy,
                                                      self.config.can_exclusion_radius)
        return free_m < CLEAR_AHEAD_M
