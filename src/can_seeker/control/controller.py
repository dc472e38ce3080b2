"""Stop-near-can controller: search for the can, drive to it, stop just in front of it.

State machine (the ``can_stopper`` node feeds it detections and asks it for a command at a
fixed rate):

- SEARCH: turn in place toward the side the can was last seen (left at start).
- APPROACH: steer on the bearing, drive at a speed set by the gap error, slow down near the
  target so the acceleration limit can stop it without overshoot, back up if too close.
- STOPPED: hold zero; drive again only when the can moves away beyond a hysteresis band;
  when the can has not been seen (with a range) for ``vanish_timeout``, LOST: it was taken away.
- LOST: the can left the view during APPROACH (or vanished while STOPPED): turn toward the
  side where it was last seen; after
  ``lost_timeout`` without it, SEARCH.

A detection message that is too old (``detection_timeout``) gives a zero command whatever the
state: a dead camera pipeline must never leave the robot driving.

Geometry (REP-103, base_link on the floor below the axle midpoint): a detection gives the
horizontal range from the camera to the can's near surface and the bearing from the camera.
The can's centre is ``camera + (range + can_radius) * (cos, sin)(camera_yaw + bearing)``; the
gap is the distance from the robot's front (a circle of ``robot_radius`` about base_link) to
the can's near surface, and the controller steers the can's centre to straight ahead of
base_link.
"""
import enum
import math
from dataclasses import dataclass
from typing import Optional, Tuple

from can_seeker.camera_geometry import CameraPose
from can_seeker.params import Param
from can_seeker.control.twist_limits import TwistLimits, limit_twist

PARAMS = (
    Param('rate', 20.0, 'rate of the /cmd_vel commands from the control timer (Hz)', 1.0, 200.0),
    Param('stop_distance', 0.25,
          'gap between the robot front and the can near surface when stopped (m)', 0.02, 3.0),
    Param('distance_tolerance', 0.01,
          'STOPPED once the gap is within this of stop_distance and the robot is at rest; '
          'the approach aims at the middle half of the band (m)', 0.001, 0.5),
    Param('bearing_tolerance_deg', 1.5,
          'STOPPED only with the can within this bearing of straight ahead; turning aims at '
          'half of it (deg)', 0.1, 30.0),
    Param('reapproach_distance', 0.05,
          'STOPPED drives again when the gap differs from stop_distance by more than this (m)',
          0.002, 1.0),
    Param('reapproach_bearing_deg', 6.0,
          'STOPPED turns again when the can bearing exceeds this (deg)', 0.2, 90.0),
    Param('max_linear', 0.4, 'forward speed limit (m/s)', 0.01, 2.0),
    Param('min_linear', 0.03,
          'slowest approach speed outside the dead-band, so the robot really arrives (m/s)',
          0.0, 0.5),
    Param('max_reverse', 0.1, 'backing-up speed limit when closer than stop_distance (m/s)',
          0.0, 1.0),
    Param('max_angular', 1.2, 'turn rate limit (rad/s)', 0.05, 6.0),
    Param('min_angular', 0.08,
          'slowest corrective turn rate outside the dead-band (rad/s)', 0.0, 1.0),
    Param('max_linear_accel', 0.5, 'linear acceleration and deceleration limit (m/s^2)',
          0.05, 5.0),
    Param('max_angular_accel', 3.0, 'angular acceleration limit (rad/s^2)', 0.1, 20.0),
    Param('linear_gain', 1.5, 'approach speed per metre of gap error (1/s)', 0.05, 10.0),
    Param('angular_gain', 2.0, 'turn rate per radian of bearing error (1/s)', 0.05, 20.0),
    Param('turn_in_place_deg', 25.0,
          'APPROACH drives forward only while the bearing is within this, at full speed when '
          'it is zero (deg)', 1.0, 90.0),
    Param('search_angular', 0.8, 'turn rate in SEARCH and LOST (rad/s)', 0.05, 3.0),
    Param('lost_timeout', 5.0, 'LOST becomes SEARCH after this long without the can (s)',
          0.0, 120.0),
    Param('vanish_timeout', 1.5, 'STOPPED becomes LOST when the can has not been seen with a '
          'range for this long (s)', 0.0, 120.0),
    Param('lockstep', False, 'answer every detection at once with a command stamped like its '
          'image (on /cmd_vel and cmd_vel_stamped; for a simulator in lockstep); the timer then '
          'sends only the zero of a stale detection'),
    Param('detection_timeout', 0.5,
          'no detection message for this long: zero Twist until one arrives (s)', 0.05, 10.0),
    Param('robot_radius', 0.165, 'radius of the robot body about base_link (m)', 0.0, 2.0),
    Param('can_radius', 0.033, 'radius of the can (m)', 0.0, 0.5),
    Param('camera_x', 0.12,
          'camera x in base_link, used only while TF has no base_link -> camera transform (m)',
          -2.0, 2.0),
)


class State(enum.Enum):
    """Controller states, published by name on ``~state``."""

    SEARCH = 'SEARCH'
    APPROACH = 'APPROACH'
    STOPPED = 'STOPPED'
    LOST = 'LOST'


@dataclass(frozen=True)
class CameraFloorPose:
    """Camera position (m) and viewing heading (rad) on the floor plane of base_link."""

    x: float
    y: float
    yaw: float


@dataclass(frozen=True)
class Sighting:
    """The can as one detection shows it, relative to base_link.

    ``bearing_rad`` is the direction of the can's centre (left positive); ``gap_m`` is the gap
    between the robot front and the can's near surface, NaN when the detection had no range.
    """

    gap_m: float
    bearing_rad: float

    @property
    def has_range(self) -> bool:
        """True when the gap is known, so the controller can drive on it."""
        return math.isfinite(self.gap_m)


def camera_floor_pose(pose: CameraPose) -> CameraFloorPose:
    """The floor-plane part of a camera pose in base_link: where it stands and where it looks."""
    return CameraFloorPose(float(pose.position[0]), float(pose.position[1]), pose.heading_rad)


def detection_problem(found: bool, range_m: float, bearing_rad: float) -> Optional[str]:
    """Why a detection claiming the can was found is malformed, or None when it is usable.

    A NaN range is normal (no usable range in that image) and is not a problem; a found can
    without a finite bearing, or with a negative or infinite range, is.
    """
    if not found:
        return None
    if not math.isfinite(bearing_rad):
        return 'detection has found=true but bearing %r' % (bearing_rad,)
    if math.isinf(range_m) or range_m < 0.0:
        return 'detection has found=true but range %r' % (range_m,)
    return None


def sighting_from_detection(found: bool, range_m: float, bearing_rad: float, camera: CameraFloorPose,
                            robot_radius: float, can_radius: float) -> Optional[Sighting]:
    """The can relative to base_link from one detection, or None when it shows no can.

    A detection without a usable range still tells on which side the can is (the camera's
    bearing has the same sign as base_link's for a camera on the robot's axis).
    """
    if not found or detection_problem(found, range_m, bearing_rad) is not None:
        return None
    heading = camera.yaw + bearing_rad
    if not math.isfinite(range_m):
        return Sighting(math.nan, heading)
    centre_x = camera.x + (range_m + can_radius) * math.cos(heading)
    centre_y = camera.y + (range_m + can_radius) * math.sin(heading)
    gap_m = math.hypot(centre_x, centre_y) - can_radius - robot_radius
    return Sighting(gap_m, math.atan2(centre_y, centre_x))


def dead_band(error: float, band: float, gain: float, minimum: float) -> float:
    """Proportional command ``gain * error``: zero inside +-``band``, at least ``minimum``
    in magnitude outside it (so small errors are really corrected)."""
    if abs(error) <= band:
        return 0.0
    return math.copysign(max(minimum, gain * abs(error)), error)


class Controller:
    """The SEARCH/APPROACH/STOPPED/LOST state machine with its control law and limits.

    Times are seconds on one clock (sim time in the node). Call :meth:`observe` for every
    detection message (found or not) and :meth:`command` at the control rate.
    """

    def __init__(self, config):
        """``config`` has the attributes named in :data:`PARAMS`."""
        self.config = config
        self.limits = TwistLimits(config.max_linear, config.max_reverse, config.max_angular,
                                  config.max_linear_accel, config.max_angular_accel)
        self.reset()

    def reset(self, now_s: float = -math.inf) -> None:
        """Back to SEARCH (turning left), at rest, with no detection seen yet.

        Detections of images taken before ``now_s`` show the world before the reset (the can
        may have been moved since) and are ignored.
        """
        self.ignore_before_s = now_s
        self.state = State.SEARCH
        self.turn_sign = 1.0
        self.sighting: Optional[Sighting] = None
        self.last_message_s: Optional[float] = None
        self.lost_since_s = 0.0
        self.seen_since_stop_s = 0.0
        self.last_command: Tuple[float, float] = (0.0, 0.0)
        self.last_command_s: Optional[float] = None

    def _errors(self) -> Tuple[float, float]:
        """(gap error m, bearing rad) of the current sighting."""
        return self.sighting.gap_m - self.config.stop_distance, self.sighting.bearing_rad

    def observe(self, sighting: Optional[Sighting], now_s: float,
                image_stamp_s: float = math.inf) -> None:
        """Take one detection message received at ``now_s`` of an image taken at
        ``image_stamp_s``: ``sighting`` is None when it showed no can."""
        if image_stamp_s < self.ignore_before_s:
            return
        self.last_message_s = now_s
        self.sighting = sighting
        if sighting is not None and sighting.bearing_rad != 0.0:
            self.turn_sign = math.copysign(1.0, sighting.bearing_rad)
        ranged = sighting is not None and sighting.has_range
        if self.state in (State.SEARCH, State.LOST):
            if ranged:
                self.state = State.APPROACH
        elif self.state is State.APPROACH:
            if not ranged:
                self.state = State.LOST
                self.lost_since_s = now_s
        elif self.state is State.STOPPED:
            self._observe_stopped(ranged, now_s)

    def _observe_stopped(self, ranged: bool, now_s: float) -> None:
        """STOPPED: approach again when the can moved, LOST when it vanished for a while."""
        if not ranged:
            if now_s - self.seen_since_stop_s > self.config.vanish_timeout:
                self.state = State.LOST
                self.lost_since_s = now_s
            return
        self.seen_since_stop_s = now_s
        gap_error, bearing = self._errors()
        if (abs(gap_error) > self.config.reapproach_distance
                or abs(bearing) > math.radians(self.config.reapproach_bearing_deg)):
            self.state = State.APPROACH

    def is_stale(self, now_s: float) -> bool:
        """True when the last detection message will be older than ``detection_timeout``
        before the next control tick: a command is executed for one control period, so the
        zero goes out no later than the timeout."""
        return (self.last_message_s is None
                or now_s + 1.0 / self.config.rate - self.last_message_s
                > self.config.detection_timeout)

    def desired(self) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) the current state asks for, before limits."""
        config = self.config
        if self.state in (State.SEARCH, State.LOST):
            return 0.0, self.turn_sign * config.search_angular
        if self.state is State.STOPPED:
            return 0.0, 0.0
        gap_error, bearing = self._errors()
        angular = dead_band(bearing, math.radians(config.bearing_tolerance_deg) / 2.0,
                            config.angular_gain, config.min_angular)
        linear = dead_band(gap_error, config.distance_tolerance / 2.0, config.linear_gain,
                           config.min_linear)
        if linear > 0.0:
            braking_speed = math.sqrt(2.0 * config.max_linear_accel * gap_error)
            heading_scale = max(0.0, 1.0 - abs(bearing) / math.radians(config.turn_in_place_deg))
            linear = min(linear, braking_speed, config.max_linear) * heading_scale
        return linear, angular

    def _settled(self, command: Tuple[float, float]) -> bool:
        """True when APPROACH has arrived: within both tolerances and at rest."""
        gap_error, bearing = self._errors()
        return (command == (0.0, 0.0)
                and abs(gap_error) <= self.config.distance_tolerance
                and abs(bearing) <= math.radians(self.config.bearing_tolerance_deg))

    def command(self, now_s: float) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) command to send at ``now_s``."""
        dt_s = 0.0 if self.last_command_s is None else now_s - self.last_command_s
        self.last_command_s = now_s
        if self.is_stale(now_s):
            self.last_command = (0.0, 0.0)
            return self.last_command
        if self.state is State.LOST and now_s - self.lost_since_s > self.config.lost_timeout:
            self.state = State.SEARCH
        linear, angular = limit_twist(self.last_command, self.desired(), dt_s, self.limits)
        # Never forward while closer than stop_distance, even if braking exceeds the limit.
        if self.sighting is not None and self.sighting.has_range and linear > 0.0:
            if self.sighting.gap_m < self.config.stop_distance:
                linear = 0.0
        self.last_command = (linear, angular)
        if self.state is State.APPROACH and self._settled(self.last_command):
            self.state = State.STOPPED
            self.seen_since_stop_s = now_s
        return self.last_command

