"""Stop-near-can controller: search for the can, drive to it, stop just in front of it.

:class:`Controller` is pure (no rospy): the ``can_stopper`` node feeds it detections, odometry,
range scans and the camera's view of the floor, and asks it for a command (linear m/s,
angular rad/s in base_link) at a fixed rate or, in lockstep, once per frame. States: SEARCH,
EXPLORE (frontier exploration, :mod:`can_seeker.control.navigation`), APPROACH, STOPPED, LOST
and WANDER (``behaviour`` wander, no can). Geometry (REP-103): a detection gives the range from
the camera to the can's near surface and the bearing; the gap is measured from the robot front
(a circle of ``robot_radius`` about base_link) to that surface.

IDLE: disarmed (``~enabled`` false, or :meth:`Controller.set_enabled` false), every command
zero; arming starts afresh with an empty map. With ``~explore`` false, SEARCH keeps turning in
place. A bumper (:meth:`Controller.observe_bump`) hands the robot to
:mod:`can_seeker.control.bump_recovery`.

Every command passes the safety layer (free travel along the command's arc through the scans,
remembered obstacles and unknown floor) and the twist limits. A stale detection gives zero; a
stale scan, odometry or camera_info allows turning only; a non-finite command is an error,
never a limit. :attr:`Controller.why` says why a command is zero or limited, and
:meth:`Controller.missing_inputs` names the missing or stale inputs.

Design, reasons and limits: docs/design/controller-and-safety.md.
"""
import enum
import math
from dataclasses import dataclass
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple

from can_seeker.camera_geometry import CameraPose
from can_seeker.camera_mount import FALLBACK_MOUNT_PARAMS
import numpy as np

from can_seeker.frames import BASE_FRAME, ODOM_FRAME
from can_seeker.health import ERROR, OK, WARN, Health
from can_seeker.params import Param
from can_seeker.control import avoidance
from can_seeker.control.bump_recovery import BumpRecovery
from can_seeker.control.navigation import CLEAR_AHEAD_M, GOAL_REACHED_M, CameraView, Navigator, \
    Pose2D
from can_seeker.control.pose_history import PoseHistory, sighting_from
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.twist_limits import TwistLimits, limit_twist, require_finite
from can_seeker.sim.lockstep import parse_topics

FALLBACK_CAMERA_X = next(spec for spec in FALLBACK_MOUNT_PARAMS if spec.name == 'camera_x')
"""The camera's fallback forward offset, declared once for every node (camera_mount)."""

PARAMS = (
    Param('enabled', True, 'start armed: searching and driving; false starts IDLE (zero '
          'commands) until the ~enable service arms it'),
    Param('explore', True, 'explore the room when a full turn in place did not show the can; '
          'false keeps the robot turning in place to search (it still drives to a can it '
          'sees)'),
    Param('bumper_topic', '', 'std_msgs/Bool contact sensor (true: the bumper is pressed): '
          'stop, back off, keep off the contact; empty: no bumper'),
    Param('camera_info_timeout', 1.0, 'with obstacle sensing, no camera_info for this long: no '
          'driving forward or back, only turning (s)', 0.05, 10.0, safer='lower'),
    Param('rate', 20.0, 'rate of the /cmd_vel commands from the control timer (Hz)', 1.0, 200.0),
    Param('stop_distance', 0.25,
          'gap between the robot front and the can near surface when stopped (m)', 0.02, 3.0,
          safer='higher'),
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
    Param('max_linear', 0.4, 'forward speed limit (m/s)', 0.01, 2.0, safer='lower'),
    Param('min_linear', 0.03,
          'slowest approach speed outside the dead-band, so the robot really arrives (m/s)',
          0.0, 0.5),
    Param('max_reverse', 0.1, 'backing-up speed limit: when closer than stop_distance, and '
          'to see floor below the camera\'s view that keeps the robot from driving (m/s)',
          0.0, 1.0, safer='lower'),
    Param('max_angular', 1.2, 'turn rate limit (rad/s)', 0.05, 6.0, safer='lower'),
    Param('min_angular', 0.08,
          'slowest corrective turn rate outside the dead-band (rad/s)', 0.0, 1.0),
    Param('max_linear_accel', 0.5, 'linear acceleration and deceleration limit (m/s^2)',
          0.05, 5.0, safer='lower'),
    Param('max_angular_accel', 3.0, 'angular acceleration limit (rad/s^2)', 0.1, 20.0,
          safer='lower'),
    Param('linear_gain', 1.5, 'approach speed per metre of gap error (1/s)', 0.05, 10.0),
    Param('angular_gain', 2.0, 'turn rate per radian of bearing error (1/s)', 0.05, 20.0),
    Param('turn_in_place_deg', 25.0,
          'the robot drives forward only while the bearing (of the can in APPROACH, of the '
          'lookahead point on grid paths) is within this, at full speed when it is zero (deg)',
          1.0, 90.0),
    Param('search_angular', 0.8, 'turn rate in SEARCH and LOST (rad/s)', 0.05, 3.0,
          safer='lower'),
    Param('lost_timeout', 5.0, 'LOST becomes SEARCH after this long without the can (s)',
          0.0, 120.0),
    Param('vanish_timeout', 1.5, 'STOPPED becomes LOST when the can has not been seen with a '
          'range for this long (s); APPROACH stops only where the can was seen with a range '
          'this recently, or where it is below the camera\'s view', 0.0, 120.0),
    Param('lockstep', False, 'answer every detection at once with a command stamped like its '
          'image (on /cmd_vel and cmd_vel_stamped; for a simulator in lockstep); the timer then '
          'sends only the zero of a stale detection'),
    Param('detection_timeout', 0.5,
          'zero Twist while the newest detection shows an image older than this, by its header '
          'stamp (by its arrival when stamped later) (s)', 0.05, 10.0, safer='lower'),
    Param('robot_radius', 0.165, 'radius of the robot body about base_link (m)', 0.0, 2.0,
          safer='higher'),
    Param('can_radius', 0.033, 'radius of the can (m)', 0.0, 0.5),
    Param('can_height', 0.122, 'height of the can, for the floor the camera covers (m)',
          0.0, 2.0),
    Param('min_confidence', 0.5,
          'act only on detections whose confidence that the red object is the can is at least '
          'this (0-1; 0 = every red object)', 0.0, 1.0),
    Param('track_confidence', 0.2,
          'while approaching or stopped at the can, a detection within ~track_gate of where '
          'the can was ranged counts as the can down to this confidence (0-1; hysteresis: '
          'close up a label\'s lettering changes the silhouette from frame to frame)', 0.0, 1.0),
    Param('track_gate', 0.3, 'how far from the tracked can a weaker detection may place it '
          '(m; 0 = no hysteresis)', 0.0, 5.0),
    FALLBACK_CAMERA_X,
    Param('behaviour', 'seek',
          'seek: search, explore, approach the can and stop; wander: drive around and turn '
          'away from obstacles, no can', choices=('seek', 'wander')),
    Param('scan_topics', 'camera_scan',
          'sensor_msgs/LaserScan topics of obstacles, separated by spaces (camera scan, lidar, '
          'both: what any of them sees is an obstacle; any frame in TF); empty: no obstacle '
          'sensing, no exploration'),
    Param('odom_topic', 'odom', 'nav_msgs/Odometry of the robot in ~odom_frame'),
    BASE_FRAME,
    ODOM_FRAME,
    Param('scan_timeout', 0.5, 'no scan for this long: no driving forward or back, only '
          'turning (s)', 0.05, 10.0, safer='lower'),
    Param('odom_timeout', 0.5, 'no odometry for this long: no exploring or path driving (s)',
          0.05, 10.0, safer='lower'),
    Param('grid_resolution', 0.1, 'cell size of the odom-frame obstacle and coverage grid (m)',
          0.02, 1.0),
    Param('map_size', 20.0, 'side of the square grid about the odom origin (m)', 2.0, 200.0),
    Param('coverage_range', 2.5,
          'farthest floor the camera counts as covered, where it still finds the can (m)',
          0.3, 20.0),
    Param('plan_margin', 0.15, 'clearance kept from obstacles on planned paths, beyond '
          'robot_radius; where no path keeps it (a narrow passage), paths keep the safety '
          'layer\'s margin (m)', 0.0, 1.0),
    Param('safety_margin', 0.05, 'clearance the safety layer keeps from any sensed obstacle, '
          'beyond robot_radius (m)', 0.0, 1.0, safer='higher'),
    Param('explore_linear', 0.3, 'cruise speed while exploring, on paths and wandering (m/s)',
          0.01, 2.0, safer='lower'),
    Param('explore_turn_cost', 0.3, 'exploration prefers goals ahead: metres of path one '
          'radian of turning is worth (m/rad)', 0.0, 10.0),
    Param('replan_period', 1.0, 'paths and exploration goals are planned again this often (s)',
          0.1, 10.0),
    Param('can_exclusion_radius', 0.25, 'range returns within this of the target can\'s '
          'estimated centre are the can (or its shadow), not an obstacle; below stop_distance '
          '+ can_radius, the direct approach never brings the robot to them (m)', 0.0, 1.0,
          safer='lower'),
    Param('obstacle_memory', 15.0, 'the safety layer avoids a remembered obstacle until scans '
          'have had it in their blind zone (nearer than range_min, at any bearing: no ray can '
          'clear a phantom there and no turn brings it into view) for this long since one last '
          'saw it; farther out of view it is kept until a scan sees its place free (s)', 1.0,
          600.0, safer='higher'),
    Param('unknown_floor_wait', 5.0, 'the safety layer keeps the robot off floor no sensor has '
          'observed; unknown floor that has been in a scan\'s blind disc (nearer than '
          'range_min, where no turn can observe it) for this long is taken for floor, unless it '
          'lies within 0.3 m of a remembered obstacle (s)', 0.5,
          600.0, safer='higher'),
    Param('wander_clearance', 0.5, 'WANDER turns away when less free travel than this lies '
          'ahead (m)', 0.05, 5.0),
)


FRONTIER_MIN_UNSEEN = 6
SAFETY_RESERVE_M = 0.03
STALL_CELLS = 5
STALL_APPROACH_M = 0.2
DIRECT_GAP_M = 0.5
STOP_ASIDE_STEP_DEG = 5.0
"""Stop points beside the straight approach are tried this far apart around the can (deg)."""
STALL_S = 6.0
APPROACH_STALL_BEYOND_MEMORY_S = 5.0
"""APPROACH and LOST that have brought the robot no ``STALL_APPROACH_M`` nearer to the can,
farther than ``DIRECT_GAP_M`` from it, for this much longer than ``~obstacle_memory`` (s)
change how they head for it (see :meth:`Controller._note_approach_progress`): a robot held
back by an obstacle it no longer sees (a phantom too) first gets the time to forget it."""
BACK_UP_BEYOND_M = 0.05
"""A robot backing up to see floor below the camera's view backs up this much farther than
that floor is below it, so the image's bottom rows see it whole."""
NOT_THERE_S = 1.0
"""LOST within reach of where the can was seen last, facing it (within
~reapproach_bearing_deg, its base in view) without seeing it for this long (s): it is not
there (moved, or a misplaced sighting put it there), so SEARCH at once instead of standing
until ~lost_timeout."""
LOOK_BELOW_FRACTION = 0.5
"""A robot kept from driving by unknown floor and turning slower than this fraction of
~search_angular turns to look at that floor instead."""
BELOW_VIEW_MARGIN_M = 0.05
"""The can counts as below the view from this far beyond the floor of the image's bottom row
(m): there its base touches the bottom edge, where the floor range gives way to the width
range, with a confidence that falls toward 0 as the silhouette is cut."""


class State(enum.Enum):
    """Controller states, published by name on ``~state``."""

    SEARCH = 'SEARCH'
    EXPLORE = 'EXPLORE'
    APPROACH = 'APPROACH'
    STOPPED = 'STOPPED'
    LOST = 'LOST'
    WANDER = 'WANDER'
    IDLE = 'IDLE'


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
    between the robot front and the can's near surface, NaN when the detection had no range;
    ``confidence`` is the detector's that the red object is the can (0-1).
    """

    gap_m: float
    bearing_rad: float
    confidence: float = 1.0

    @property
    def has_range(self) -> bool:
        """True when the gap is known, so the controller can drive on it."""
        return math.isfinite(self.gap_m)


class MissingInput(NamedTuple):
    """An input the controller lacks: its ``name`` ('detection', 'odometry', 'camera_info'
    or a scan topic),
    the ``problem``, e.g. 'no odometry for 1.20 s (timeout 0.50 s)', 'no scan on /scan yet',
    and whether it is ``overdue``: not just awaited since a reset, within its timeout."""

    name: str
    problem: str
    overdue: bool = True


def _missing(name: str, what: str, stamp_s: Optional[float], timeout_s: float, now_s: float,
             reset_s: float) -> MissingInput:
    """An input last seen at ``stamp_s`` (None: not since the reset at ``reset_s``), stale at
    ``now_s``: older than ``timeout_s`` now or by the next command."""
    if stamp_s is None:
        return MissingInput(name, 'no %s yet' % what, now_s - reset_s > timeout_s)
    age_s = now_s - stamp_s
    return MissingInput(name, 'no %s for %.2f s (timeout %.2f s%s)' % (
        what, age_s, timeout_s, ' by the next command' if age_s <= timeout_s else ''))


def problems_text(missing: Sequence[MissingInput]) -> str:
    """The problems of ``missing``, in one line."""
    return '; '.join(item.problem for item in missing)


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


def detection_shows_can(found: bool, confidence: float, min_confidence: float) -> bool:
    """Whether a detection is taken as the can: a red object (found) that the detector is
    at least ``min_confidence`` sure is the can (not a red book, flag or toy)."""
    return found and confidence >= min_confidence


def sighting_from_detection(found: bool, range_m: float, bearing_rad: float,
                            camera: CameraFloorPose,
                            robot_radius: float, can_radius: float,
                            confidence: float = 1.0) -> Optional[Sighting]:
    """The red object of one detection relative to base_link, or None when it shows none.

    A detection without a usable range still tells on which side the object is (the camera's
    bearing has the same sign as base_link's for a camera on the robot's axis).
    """
    if not found or detection_problem(found, range_m, bearing_rad) is not None:
        return None
    heading = camera.yaw + bearing_rad
    if not math.isfinite(range_m):
        return Sighting(math.nan, heading, confidence)
    centre_x = camera.x + (range_m + can_radius) * math.cos(heading)
    centre_y = camera.y + (range_m + can_radius) * math.sin(heading)
    gap_m = math.hypot(centre_x, centre_y) - can_radius - robot_radius
    return Sighting(gap_m, math.atan2(centre_y, centre_x), confidence)


def dead_band(error: float, band: float, gain: float, minimum: float) -> float:
    """Proportional command ``gain * error``: zero inside +-``band``, at least ``minimum``
    in magnitude outside it (so small errors are really corrected)."""
    if abs(error) <= band:
        return 0.0
    return math.copysign(max(minimum, gain * abs(error)), error)


class Controller:
    """The SEARCH/EXPLORE/APPROACH/STOPPED/LOST (or WANDER) state machine with its control law,
    limits and safety layer.

    Times are seconds on one clock (sim time in the node). Call :meth:`observe` for every
    detection message (found or not), :meth:`observe_pose` for odometry,
    :meth:`observe_scan` for range scans, and :meth:`command` at the control rate.
    """

    def __init__(self, config, camera_info_topic: str = 'camera_info',
                 arm_hint: str = 'call the enable service with true'):
        """``config`` has the attributes named in :data:`PARAMS`; ``camera_info_topic``
        names that input (as resolved) in the missing inputs, ``arm_hint`` says how to arm
        the node in the diagnostics while it is disarmed."""
        self.config = config
        self.camera_info_topic = camera_info_topic
        self.arm_hint = arm_hint
        self.enabled = bool(config.enabled)
        self.bump = BumpRecovery(config.robot_radius, config.max_reverse)
        self.scan_sources = parse_topics(config.scan_topics)
        self.limits = TwistLimits(config.max_linear, config.max_reverse, config.max_angular,
                                  config.max_linear_accel, config.max_angular_accel)
        self.navigator = Navigator(config.grid_resolution, config.map_size, config.robot_radius,
                                   config.plan_margin, config.safety_margin,
                                   config.obstacle_memory, config.unknown_floor_wait)
        self.camera_view: Optional[CameraView] = None
        self.reset()

    @property
    def wander(self) -> bool:
        return self.config.behaviour == 'wander'

    @property
    def senses_obstacles(self) -> bool:
        return bool(self.scan_sources)

    @property
    def needs_camera_info(self) -> bool:
        """True when driving depends on the camera's view: seeking with obstacle sensing."""
        return self.senses_obstacles and not self.wander

    def reset(self, now_s: float = -math.inf) -> None:
        """Back to SEARCH (turning left; IDLE while disarmed), at rest, with no detection
        seen yet and an empty map.

        Detections of images taken before ``now_s`` show the world before the reset (the can
        may have been moved since) and are ignored; so is camera_info that came before.
        """
        self.ignore_before_s = now_s
        self._enter(State.IDLE if not self.enabled else
                    State.WANDER if self.wander else State.SEARCH)
        self.camera_info_s: Optional[float] = None
        self.bump.cancel()
        self.turn_sign = 1.0
        self.sighting: Optional[Sighting] = None
        self.can_xy: Optional[Tuple[float, float]] = None
        self.poses = PoseHistory()
        self.last_image_s: Optional[float] = None
        self.lost_since_s = 0.0
        self.seen_since_stop_s = 0.0
        self.ranged_seen_s = -math.inf
        self.last_command: Tuple[float, float] = (0.0, 0.0)
        self.last_command_s: Optional[float] = None
        self.navigator.reset()
        self.pose_s: Optional[float] = None
        self.scan_s: Dict[str, float] = {}
        self.why = '' if self.enabled else self._disarmed_reason()
        self.planned_s = -math.inf

    # Inputs ----------------------------------------------------------------------------------

    def _errors(self) -> Tuple[float, float]:
        """(gap error m, bearing rad) of the current sighting."""
        return self.sighting.gap_m - self.config.stop_distance, self.sighting.bearing_rad

    def _enter(self, state: State) -> None:
        """Switch to ``state`` with its per-state memory (turn searched, exploration goal and
        path, progress, since when LOST faces the can's last place) started afresh."""
        self.state = state
        self.facing_lost_s: Optional[float] = None
        self.searched_rad = 0.0
        self.goal_xy: Optional[np.ndarray] = None
        self.goal_is_candidate = False
        self.path_xy: Optional[np.ndarray] = None
        self.progress: Optional[Tuple[int, float, float, Optional[np.ndarray]]] = None
        self.stop_aside: Optional[float] = None
        self.backing: Optional[Tuple[float, float, float]] = None
        if state not in (State.APPROACH, State.LOST):
            self.approach_progress: Optional[Tuple[float, float]] = None
            self.keep_to_path = False

    def observe(self, sighting: Optional[Sighting], now_s: float,
                image_stamp_s: float = math.inf) -> None:
        """Take one detection message received at ``now_s`` of an image taken at
        ``image_stamp_s``: ``sighting`` is its red object (None when it showed none), taken
        as the can by its confidence (see :meth:`_shows_can`). The detection is as fresh as its
        image (an old image that arrives late is no news), but never fresher than its arrival
        (a clock ahead of ours must not keep it fresh). The can is placed in odom from the pose
        at the image's stamp, and its gap and bearing are then taken from the pose now: the
        robot moved while the frame was on its way."""
        if image_stamp_s < self.ignore_before_s or self.wander:
            return
        self.last_image_s = min(now_s, image_stamp_s)
        can_xy = None if sighting is None else self._can_xy_of(
            sighting, self.poses.at(min(now_s, image_stamp_s)))
        if sighting is not None and not self._shows_can(sighting, can_xy):
            sighting, can_xy = None, None
        self.sighting = sighting if can_xy is None else self._sighting_now(can_xy,
                                                                          sighting.confidence)
        if self.camera_view is not None:
            self.navigator.mark_seen(self.camera_view)
        if sighting is not None and sighting.bearing_rad != 0.0:
            self.turn_sign = math.copysign(1.0, sighting.bearing_rad)
        ranged = sighting is not None and sighting.has_range
        if ranged:
            self.ranged_seen_s = now_s
        if (not ranged and self.state in (State.APPROACH, State.STOPPED)
                and (self.can_below_view() or self.stop_aside is not None
                     or self._keeping_to_path())):
            # The camera cannot range the can there, or the can left the view while the
            # robot heads for a stop point aside or keeps to a path around an obstacle: go on
            # with where it was ranged last.
            self.sighting = self._sighting_now(self.can_xy, self.sighting.confidence
                                               if self.sighting is not None else 0.0)
            ranged = True
        if can_xy is not None:
            self.can_xy = can_xy
        if self.state in (State.SEARCH, State.EXPLORE, State.LOST):
            if ranged:
                self._enter(State.APPROACH)
        elif self.state is State.APPROACH:
            if not ranged:
                self._enter(State.LOST)
                self.lost_since_s = now_s
        elif self.state is State.STOPPED:
            self._observe_stopped(ranged, now_s)

    def _sighting_now(self, can_xy: Tuple[float, float], confidence: float) -> Sighting:
        """The can centred at ``can_xy`` (odom) as seen from the latest pose."""
        gap_m, bearing_rad = sighting_from(can_xy, self.navigator.pose, self.config.robot_radius,
                                           self.config.can_radius)
        return Sighting(gap_m, bearing_rad, confidence)

    def can_below_view(self) -> bool:
        """True when the tracked can's near surface is nearer the camera, along its heading,
        than the floor of the image's bottom row plus ``BELOW_VIEW_MARGIN_M``: its base is
        below the image, so the detector cannot range it (or see it at all). False without a
        tracked can, a pose or a camera view that knows its bottom row."""
        view, pose = self.camera_view, self.navigator.pose
        if view is None or view.base_near_m <= 0.0 or self.can_xy is None or pose is None:
            return False
        dx, dy = self.can_xy[0] - pose.x, self.can_xy[1] - pose.y
        cos_yaw, sin_yaw = math.cos(pose.yaw), math.sin(pose.yaw)
        can_x = cos_yaw * dx + sin_yaw * dy - view.x
        can_y = -sin_yaw * dx + cos_yaw * dy - view.y
        forward_m = (can_x * math.cos(view.yaw) + can_y * math.sin(view.yaw)
                     - self.config.can_radius)
        return forward_m < view.base_near_m + BELOW_VIEW_MARGIN_M

    def _keeping_to_path(self) -> bool:
        """True while APPROACH keeps to a grid path to the can after a stall (see
        :meth:`_note_approach_progress`) and the can is farther than ``DIRECT_GAP_M``."""
        return (self.keep_to_path and self.can_xy is not None and self.navigator.pose is not None
                and self._beyond_direct_gap())

    def _beyond_direct_gap(self) -> bool:
        """True while the gap to where the can was ranged last (odom; needs ``can_xy`` and a
        pose) is wider than ``DIRECT_GAP_M``, the last stretch the direct law drives."""
        return self._sighting_now(self.can_xy, 0.0).gap_m > DIRECT_GAP_M

    def _can_xy_of(self, sighting: Sighting,
                   pose: Optional[Pose2D]) -> Optional[Tuple[float, float]]:
        """Where a ranged sighting from ``pose`` puts the can's centre in odom (None without
        range or pose)."""
        if not sighting.has_range or pose is None:
            return None
        distance = sighting.gap_m + self.config.robot_radius + self.config.can_radius
        return (pose.x + distance * math.cos(pose.yaw + sighting.bearing_rad),
                pose.y + distance * math.sin(pose.yaw + sighting.bearing_rad))

    def _shows_can(self, sighting: Sighting, can_xy: Optional[Tuple[float, float]]) -> bool:
        """A red object (placing the can at ``can_xy`` in odom, None if unknown) is the can
        when the detector is ~min_confidence sure; while the can is approached or stopped at,
        also down to ~track_confidence where it was ranged last (within ~track_gate): its
        silhouette close up varies from frame to frame."""
        if detection_shows_can(True, sighting.confidence, self.config.min_confidence):
            return True
        if (self.state not in (State.APPROACH, State.STOPPED) or self.can_xy is None
                or can_xy is None
                or not detection_shows_can(True, sighting.confidence,
                                           self.config.track_confidence)):
            return False
        return math.hypot(can_xy[0] - self.can_xy[0],
                          can_xy[1] - self.can_xy[1]) < self.config.track_gate

    def _observe_stopped(self, ranged: bool, now_s: float) -> None:
        """STOPPED: approach again when the can moved, LOST when it vanished for a while."""
        if not ranged:
            if elapsed_s(now_s, self.seen_since_stop_s) > self.config.vanish_timeout:
                self._enter(State.LOST)
                self.lost_since_s = now_s
            return
        self.seen_since_stop_s = now_s
        gap_error, bearing = self._errors()
        if (abs(gap_error) > self.config.reapproach_distance
                or abs(bearing) > math.radians(self.config.reapproach_bearing_deg)):
            self._enter(State.APPROACH)
    def observe_pose(self, pose: Pose2D, now_s: float,
                     stamp_s: Optional[float] = None) -> None:
        """Odometry: base_link's pose in odom received at ``now_s``, stamped ``stamp_s``
        (default: ``now_s``); counts the turn made in SEARCH, and keeps the gap and bearing of
        the can seen last up to date with the robot's motion."""
        previous = self.navigator.pose
        if previous is not None and self.state is State.SEARCH:
            self.searched_rad += abs(avoidance.wrap_angle(pose.yaw - previous.yaw))
        self.navigator.pose = pose
        self.pose_s = now_s
        self.poses.add(now_s if stamp_s is None else stamp_s, pose)
        if self.sighting is not None and self.sighting.has_range and self.can_xy is not None:
            self.sighting = self._sighting_now(self.can_xy, self.sighting.confidence)

    def observe_scan(self, source: str, ends_base: np.ndarray, hits: np.ndarray, origin_base,
                     now_s: float, range_min_m: float = 0.0, stamp_s: float = math.inf):
        """A range scan of sensor ``source`` (one of the ``scan_topics``) in base_link (see
        :meth:`Navigator.add_scan`) received at ``now_s``, taken at ``stamp_s``: placed in
        odom from the pose then (never later than its arrival), like a detection. A camera
        scan comes as late as its frame, and the robot turned since: placed at the pose it
        arrived at, it smeared obstacles by the turn (8 deg at 1.2 rad/s and 0.12 s)."""
        if self.navigator.pose is None:
            return
        pose = self.poses.at(min(now_s, stamp_s)) or self.navigator.pose
        self.navigator.add_scan(ends_base, hits, origin_base, pose, range_min_m, now_s, source)
        self.scan_s[source] = now_s

    def set_camera_view(self, view: CameraView) -> None:
        """The camera's floor footprint in base_link, for coverage."""
        self.camera_view = view

    def observe_camera_info(self, now_s: float) -> None:
        """A usable camera_info arrived at ``now_s`` (the camera's intrinsics, for its view)."""
        self.camera_info_s = now_s

    def set_enabled(self, enabled: bool, now_s: float) -> str:
        """Arm (from SEARCH or WANDER, with a fresh map, as :meth:`reset`) or disarm (IDLE:
        every command zero, from this call on); returns what was done, in a sentence."""
        if enabled == self.enabled:
            return 'already %s' % ('armed' if enabled else 'disarmed')
        self.enabled = enabled
        self.reset(now_s)
        if enabled:
            return 'armed: %s' % self.state.value
        self.last_command = (0.0, 0.0)
        self.why = self._disarmed_reason()
        return 'disarmed: zero commands until armed again'

    def _disarmed_reason(self) -> str:
        return 'disarmed (to arm: %s)' % self.arm_hint

    def observe_bump(self, pressed: bool, now_s: float) -> bool:
        """A bumper message at ``now_s``. A new touch (a press after a release) while armed
        stops the robot at once (the next command starts from rest), keeps the contact (the
        robot's front on its heading) in the obstacle map and starts the back-off; returns
        True then, so the node sends the stop without waiting for the next tick."""
        if not self.enabled:
            self.bump.pressed = pressed
            return False
        was_pressed = self.bump.pressed
        contact = self.bump.bumped(pressed, self.navigator.pose, now_s)
        if not pressed or was_pressed:
            return False
        if contact is not None:
            self.navigator.grid.add_contact(contact)
        self.path_xy = None
        self.last_command = (0.0, 0.0)
        return True

    def is_stale(self, now_s: float) -> bool:
        """True when the image of the last detection message will be older than
        ``detection_timeout`` before the next control tick: a command is executed for one
        control period, so the zero goes out no later than the timeout. WANDER needs no
        detections."""
        if self.wander:
            return not self._fresh(self.pose_s, self.config.odom_timeout, now_s)
        return not self._fresh(self.last_image_s, self.config.detection_timeout, now_s)

    def _fresh(self, stamp_s: Optional[float], timeout_s: float, now_s: float) -> bool:
        return stamp_s is not None and now_s + 1.0 / self.config.rate - stamp_s <= timeout_s

    def can_navigate(self, now_s: float) -> bool:
        """True when odometry and every sensor's scan are fresh enough to drive on grid
        paths (and to drive at all, with obstacle sensing)."""
        return self.senses_obstacles and not self._sensing_problems(now_s)

    def missing_inputs(self, now_s: float) -> List[MissingInput]:
        """What keeps the robot from driving: the detection when it is stale and, with obstacle
        sensing (or in WANDER), odometry and each sensor's scan when missing or older than
        their timeouts."""
        missing = []
        if not self.wander and self.is_stale(now_s):
            missing.append(_missing('detection', 'detection', self.last_image_s,
                                    self.config.detection_timeout, now_s,
                                    self.ignore_before_s))
        if self.senses_obstacles or self.wander:
            missing += self._sensing_problems(now_s)
        return missing

    def _sensing_problems(self, now_s: float) -> List[MissingInput]:
        """Odometry, the scans of every sensor and (see :attr:`needs_camera_info`)
        camera_info, when missing or stale."""
        config = self.config
        problems = []
        if not self._fresh(self.pose_s, config.odom_timeout, now_s):
            problems.append(_missing('odometry', 'odometry', self.pose_s, config.odom_timeout,
                                     now_s, self.ignore_before_s))
        for source in self.scan_sources:
            if not self._fresh(self.scan_s.get(source), config.scan_timeout, now_s):
                problems.append(_missing(source, 'scan on %s' % source, self.scan_s.get(source),
                                         config.scan_timeout, now_s, self.ignore_before_s))
        if self.needs_camera_info and not self._fresh(self.camera_info_s,
                                                      config.camera_info_timeout, now_s):
            problems.append(_missing('camera_info', 'camera_info on %s' % self.camera_info_topic,
                                     self.camera_info_s, config.camera_info_timeout, now_s,
                                     self.ignore_before_s))
        return problems

    def health(self, now_s: float, why: Optional[str] = None) -> Health:
        """The control status for /diagnostics: ERROR while an input is overdue (WARN while
        one is awaited after a reset), and the state with why its last command is zero or
        limited (``why``, else :attr:`why`), or what it commands."""
        missing = self.missing_inputs(now_s)
        why = self.why if why is None else why
        linear, angular = self.last_command
        doing = why or 'commanding %.2f m/s, %.2f rad/s' % (linear, angular)
        values = (('state', self.state.value), ('armed', 'yes' if self.enabled else 'no'),
                  ('linear (m/s)', '%.3f' % linear),
                  ('angular (rad/s)', '%.3f' % angular), ('why', why or 'none'),
                  ('missing inputs', problems_text(missing) or 'none'),
                  ('bumps', str(self.bump.count)))
        level = ERROR if any(item.overdue for item in missing) else WARN if missing else OK
        if not self.enabled:
            # Nothing drives while disarmed: a missing input is a warning for when it is armed.
            level = min(level, WARN)
        return Health(level, '%s: %s' % (self.state.value, doing), values)

    def _because(self, reason: str) -> None:
        """Say why this tick's command is zero or limited (the first reason found stands)."""
        if not self.why:
            self.why = reason

    # Behaviours ------------------------------------------------------------------------------

    def _approach_law(self, aim_bearing_rad: Optional[float] = None) -> Tuple[float, float]:
        """The direct approach: steer on the bearing, speed from the gap error. While it drives
        forward it steers on ``aim_bearing_rad`` instead when given (a stop point beside the
        straight line, :meth:`_stop_aside_bearing`); in the stop band it faces the can."""
        config = self.config
        gap_error, bearing = self._errors()
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

    def _stop_aside_bearing(self) -> Optional[float]:
        """Bearing (rad, base_link) of a stop point beside the straight approach, or None.

        The robot may stop at the can from any side: on the circle ``stop_distance`` from its
        surface. Where the safety layer holds the straight approach back before that circle
        (an obstacle beside the last stretch, often one remembered out of the camera's view or
        in its blind disc, where no turn can clear it), the robot drives straight to the point
        of the circle nearest the straight line's own (``STOP_ASIDE_STEP_DEG`` apart, up to a
        quarter turn around the can) that the safety layer lets it reach. It keeps that point
        (as its direction from the can's centre, in odom) until it arrives (in the stop band
        the direct law turns it to face the can) or the way there is blocked; the can may
        leave the view meanwhile (see :meth:`observe`). None while the straight line reaches
        its own stop point, or when no point is in reach."""
        config, pose = self.config, self.navigator.pose
        can = np.asarray(self.can_xy, float)
        ring_m = config.stop_distance + config.robot_radius + config.can_radius
        if self.stop_aside is not None:
            point = can + ring_m * np.array((math.cos(self.stop_aside),
                                             math.sin(self.stop_aside)))
            point_base = avoidance.to_frame(point, pose.x, pose.y, pose.yaw)
            if self._reachable(point_base)[0]:
                return math.atan2(point_base[0, 1], point_base[0, 0])
            self.stop_aside = None
        away = np.array((pose.x, pose.y)) - can
        steps = np.radians(STOP_ASIDE_STEP_DEG) * np.arange(
            1, int(90.0 // STOP_ASIDE_STEP_DEG) + 1)
        around = math.atan2(away[1], away[0]) + np.concatenate(
            ([0.0], np.stack((steps, -steps), axis=1).reshape(-1)))
        points = can + ring_m * np.stack((np.cos(around), np.sin(around)), axis=1)
        points_base = avoidance.to_frame(points, pose.x, pose.y, pose.yaw)
        if self._reachable(points_base[:1])[0]:
            return None
        chosen = np.nonzero(self._reachable(points_base[1:]))[0] + 1
        if len(chosen) == 0:
            return None
        self.stop_aside = float(around[chosen[0]])
        return math.atan2(points_base[chosen[0], 1], points_base[chosen[0], 0])

    def _reachable(self, points_base: np.ndarray) -> np.ndarray:
        """Which stop points (N x 2, base_link) a straight drive reaches, within the stop band,
        before the safety layer stops it."""
        needed_m = (np.linalg.norm(points_base, axis=1) - self.config.distance_tolerance / 2.0
                    + SAFETY_RESERVE_M)
        travel_m = self.navigator.free_travel_toward_m(points_base, self.can_xy,
                                                       self.config.can_exclusion_radius)
        return travel_m >= needed_m

    def _follow_path(self, goal_xy, now_s: float, exclude_xy=None) -> Optional[Tuple[float, float]]:
        """Drive along a grid path to ``goal_xy`` (planned again every ``replan_period``), or
        None when no path reaches it."""
        config = self.config
        if self.path_xy is None or elapsed_s(now_s, self.planned_s) >= config.replan_period:
            self.path_xy = self.navigator.path_to(goal_xy, exclude_xy, config.can_exclusion_radius,
                                                  self.path_xy)
            self.planned_s = now_s
        if self.path_xy is None:
            return None
        command, why = self.navigator.follow(self.path_xy, config.explore_linear,
                                             math.radians(config.turn_in_place_deg),
                                             config.angular_gain)
        if why:
            self._because(why)
        return command

    def _explore(self, now_s: float) -> Tuple[float, float]:
        """Head for the nearest place an all-round scan showed a small object standing free
        that the camera has not had in view (the can, maybe), else for the best floor not
        covered yet; SEARCH again on arrival (a place where the can may stand then counts as
        looked at: on the way a can there would have come into view)."""
        navigator, config = self.navigator, self.config
        covered = (self.goal_xy is not None
                   and (navigator.candidate_viewed(self.goal_xy) if self.goal_is_candidate
                        else navigator.is_seen(self.goal_xy)))
        if (self.goal_xy is None or covered
                or elapsed_s(now_s, self.planned_s) >= config.replan_period):
            previous_goal, previous_is_candidate = self.goal_xy, self.goal_is_candidate
            self.goal_xy = navigator.unviewed_candidate()
            self.goal_is_candidate = self.goal_xy is not None
            if self.goal_xy is None:
                self.goal_xy = navigator.frontier(
                    config.explore_turn_cost, FRONTIER_MIN_UNSEEN,
                    None if previous_goal is None or previous_is_candidate else previous_goal)
            if (self.goal_xy is None or previous_goal is None
                    or not np.array_equal(self.goal_xy, previous_goal)):
                self.path_xy = None
            if self.goal_xy is None:
                navigator.grid.forget_coverage()
                self._enter(State.SEARCH)
                return 0.0, self.turn_sign * config.search_angular
        if navigator.distance_to(self.goal_xy) < GOAL_REACHED_M:
            if self.goal_is_candidate:
                navigator.give_up_on(self.goal_xy)
            self._enter(State.SEARCH)
            return 0.0, self.turn_sign * config.search_angular
        command = self._follow_path(self.goal_xy, now_s,
                                    self.goal_xy if self.goal_is_candidate else None)
        if command is None:
            navigator.give_up_on(self.goal_xy)
            self.goal_xy = None
            self._because('no path to the exploration goal: choosing another')
            return 0.0, 0.0
        return command

    def _toward_can(self, now_s: float) -> Tuple[float, float]:
        """APPROACH: the direct law, or a path around obstacles while the straight line to the
        can crosses obstacles grown by the robot's radius and safety margin (never in the last
        ``DIRECT_GAP_M``, where the direct law stops in front of the can, or beside the
        straight line when an obstacle holds that back: :meth:`_stop_aside_bearing`). Within
        ``distance_tolerance`` of the stop distance it only faces the can: a stop point aside,
        sought whenever the gap's estimate crossed half the tolerance, turned it away and back
        again without end. After a stall it keeps to the path whether or not the straight line
        is clear (:meth:`_note_approach_progress`)."""
        if (self.can_xy is not None and self.can_navigate(now_s)
                and self.sighting.gap_m > DIRECT_GAP_M
                and (self.keep_to_path
                     or self.navigator.straight_line_blocked(self.can_xy, self.can_xy,
                                                             self.config.can_exclusion_radius)
                     or self._direct_law_held_back())):
            command = self._follow_path(self.can_xy, now_s, self.can_xy)
            if command is not None:
                return command
            if self.keep_to_path and self._can_back_up(self.can_xy,
                                                       self.config.can_exclusion_radius):
                self._because('keeping to a path to the can, none found: backing up to see '
                              'the way')
                return -self.config.max_reverse, 0.0
        self.path_xy = None
        aside = None
        if (self.can_xy is not None and self.can_navigate(now_s)
                and self.sighting.gap_m <= DIRECT_GAP_M
                and self._errors()[0] > self.config.distance_tolerance):
            aside = self._stop_aside_bearing()
        command = self._approach_law(aside)
        if command[0] == 0.0:
            self._because(self._direct_law_standing_reason() if aside is None else
                          'an obstacle holds the straight approach back: turning to a stop '
                          'point beside it, %.0f deg off' % math.degrees(aside))
        return command

    def _direct_law_standing_reason(self) -> str:
        """Why the direct law drives neither forward nor back: the gap is in the stop band, or
        the can is too far to the side to drive yet."""
        config = self.config
        gap_error, bearing = self._errors()
        if abs(gap_error) <= config.distance_tolerance / 2.0:
            return ('deadband: gap within %.1f mm of stop_distance, bearing %.2f deg'
                    % (1000.0 * abs(gap_error), math.degrees(bearing)))
        return ('turning to the can first: bearing %.1f deg, driving within %.1f deg'
                % (math.degrees(bearing), config.turn_in_place_deg))

    def _direct_law_held_back(self) -> bool:
        """True when the safety layer would stop the direct law within ``CLEAR_AHEAD_M`` (an
        obstacle beside the straight line, nearer than the margin): the path follower then
        turns to a gap instead of stalling there."""
        command = self._approach_law()
        if command[0] <= 0.0:
            return False
        free_m = self.navigator.free_travel_m(command, self.can_xy,
                                              self.config.can_exclusion_radius)
        return free_m < CLEAR_AHEAD_M

    def _lost(self, now_s: float) -> Tuple[float, float]:
        """LOST: back toward where the can was, else turn toward the side it left."""
        config = self.config
        turning = 0.0, self.turn_sign * config.search_angular
        if self.can_xy is None or not self.can_navigate(now_s):
            self._because(self._cannot_navigate_reason(now_s, 'turning toward where the can '
                                                        'was seen'))
            return turning
        pose = self.navigator.pose
        can_base = avoidance.to_frame(np.array(self.can_xy), pose.x, pose.y, pose.yaw)[0]
        reach_m = config.robot_radius + config.can_radius + config.stop_distance
        if np.hypot(*can_base) < reach_m + GOAL_REACHED_M:
            facing = (abs(math.atan2(can_base[1], can_base[0]))
                      <= math.radians(config.reapproach_bearing_deg) and not self.can_below_view())
            if not facing:
                self.facing_lost_s = None
            elif self.facing_lost_s is None:
                self.facing_lost_s = now_s
            elif elapsed_s(now_s, self.facing_lost_s) >= NOT_THERE_S:
                self._enter(State.SEARCH)
                self._because('the can is not where it was seen last: searching')
                return turning
            self._because('turning toward where the can was seen last' if not facing else
                          'facing where the can was seen last, it is not in view')
            return avoidance.steer_to_point(can_base, 0.0, 1.0, config.angular_gain)
        command = self._follow_path(self.can_xy, now_s, self.can_xy)
        return turning if command is None else command

    def _wander(self) -> Tuple[float, float]:
        """WANDER: straight on while the way ahead is clear, else turn away in place."""
        config = self.config
        points, clearance = self.navigator.obstacles_base()
        ahead_m = avoidance.free_travel_m(points, config.explore_linear, 0.0, clearance,
                                          config.wander_clearance)
        if ahead_m >= config.wander_clearance:
            return config.explore_linear, 0.0
        if self.last_command[1] != 0.0:
            return 0.0, math.copysign(config.search_angular, self.last_command[1])
        self.turn_sign = avoidance.open_turn_sign(points, self.turn_sign)
        return 0.0, self.turn_sign * config.search_angular

    def desired(self, now_s: float = 0.0) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) the current state asks for, before limits."""
        config = self.config
        if self.state is State.IDLE:
            return 0.0, 0.0
        if self.state is State.WANDER:
            return self._wander()
        if self.state is State.SEARCH:
            if self.searched_rad < 2.0 * math.pi:
                return 0.0, self.turn_sign * config.search_angular
            if not config.explore:
                self._because('searched a full turn, ~explore is false: turning on in place')
                return 0.0, self.turn_sign * config.search_angular
            if not self.can_navigate(now_s):
                self._because(self._cannot_navigate_reason(now_s, 'searched a full turn, '
                                                           'cannot explore'))
                return 0.0, self.turn_sign * config.search_angular
            self._enter(State.EXPLORE)
        if self.state is State.EXPLORE:
            if not self.can_navigate(now_s):
                self._because(self._cannot_navigate_reason(now_s, 'cannot explore'))
                return 0.0, 0.0
            return self._explore(now_s)
        if self.state is State.LOST:
            return self._lost(now_s)
        if self.state is State.STOPPED:
            self._because('stopped at the can')
            return 0.0, 0.0
        return self._toward_can(now_s)

    def _cannot_navigate_reason(self, now_s: float, consequence: str) -> str:
        """Why grid paths are out of reach (stale inputs, or no obstacle sensing at all)."""
        problems = (problems_text(self._sensing_problems(now_s)) if self.senses_obstacles
                    else 'no obstacle sensing (no scan topics)')
        return '%s: %s' % (problems, consequence)

    def _safe(self, command: Tuple[float, float], now_s: float,
              look: bool = False) -> Tuple[float, float]:
        """The safety layer: speed, forward or backward, within what the sensed obstacles
        allow along the command's arc. With ``look``, a robot that unknown floor ahead keeps
        from driving, and that is not turning, turns toward that floor at ~search_angular so
        the camera observes it (no turn is ever limited)."""
        linear, angular = command
        if look and linear <= 0.0:
            self.backing = None
        if not self.senses_obstacles or linear == 0.0:
            return command
        problems = self._sensing_problems(now_s)
        if problems:
            self._because('%s: no driving, only turning' % problems_text(problems))
            return 0.0, angular
        exclude = self.can_xy if self.state in (State.APPROACH, State.LOST) else None
        radius = self.config.can_exclusion_radius
        if look and self.backing is not None:
            backed_m = self.navigator.distance_to(self.backing[:2])
            if backed_m < self.backing[2] and self._can_back_up(exclude, radius):
                self._because('floor below the camera\'s view ahead: backing up %.2f of %.2f m '
                              'to see it' % (backed_m, self.backing[2]))
                return -self.config.max_reverse, 0.0
            self.backing = None
        free_m, unknown_point = self.navigator.safety_block(command, exclude, radius)
        safe = avoidance.safe_linear(linear, free_m, self.config.max_linear_accel,
                                     SAFETY_RESERVE_M)
        if abs(safe) < abs(linear):
            unknown = unknown_point is not None
            reason = ('%s %s: %.2f m of free travel, speed capped at %.2f m/s'
                      % ('floor not yet seen' if unknown else 'obstacle',
                         'ahead' if linear > 0.0 else 'behind', free_m, abs(safe)))
            if look and unknown and safe == 0.0 and linear > 0.0:
                hidden_m = self._below_view_m(unknown_point)
                if hidden_m > 0.0 and self._can_back_up(exclude, radius):
                    pose = self.navigator.pose
                    self.backing = (pose.x, pose.y, hidden_m + BACK_UP_BEYOND_M)
                    self._because(reason + ', below the camera\'s view: backing up to see it')
                    return -self.config.max_reverse, 0.0
                if abs(angular) < LOOK_BELOW_FRACTION * self.config.search_angular:
                    angular = math.copysign(self.config.search_angular, unknown_point[1] or 1.0)
                    reason += ', turning to look at it'
            self._because(reason)
        return safe, angular

    def _below_view_m(self, point_base: np.ndarray) -> float:
        """How far (m) the robot must back up for floor point ``point_base`` (base_link) to
        come half a grid cell inside the image's floor (see
        :meth:`CameraView.back_up_to_see_m`; 0 when it is in view, no backing up brings it
        there or the view is not known): beside the robot's front, below the narrow bottom of
        a steep camera's view, that is farther than below its middle, and no turn in place
        brings such floor into view."""
        view = self.camera_view
        if view is None or view.base_near_m <= 0.0:
            return 0.0
        back_m = view.back_up_to_see_m(point_base, self.navigator.grid.resolution_m / 2.0)
        return back_m if math.isfinite(back_m) else 0.0

    def _can_back_up(self, exclude, radius_m: float) -> bool:
        """True when the safety layer lets the robot back up at ~max_reverse."""
        reverse = (-self.config.max_reverse, 0.0)
        free_m, _ = self.navigator.safety_block(reverse, exclude, radius_m)
        return avoidance.safe_linear(reverse[0], free_m, self.config.max_linear_accel,
                                     SAFETY_RESERVE_M) != 0.0

    def _settled(self, command: Tuple[float, float]) -> bool:
        """True when APPROACH has arrived: within both tolerances and at rest."""
        gap_error, bearing = self._errors()
        return (command == (0.0, 0.0)
                and abs(gap_error) <= self.config.distance_tolerance
                and abs(bearing) <= math.radians(self.config.bearing_tolerance_deg))

    def _note_progress(self, now_s: float) -> None:
        """EXPLORE gives up its goal when in ``STALL_S`` the camera has covered fewer than
        ``STALL_CELLS`` new cells and, on the way to a place where the can may stand (which
        lies across floor already covered), the robot has not come ``STALL_APPROACH_M``
        nearer to it: the goal cannot be seen from where the robot can go, or the safety layer
        keeps it from getting there. Such a place chosen after floor, or after a place now
        looked at, has its own ``STALL_S`` (not when the robot switches between two places it
        has not looked at yet, which would never run out)."""
        if self.state is not State.EXPLORE:
            self.progress = None
            return
        covered = int(np.count_nonzero(self.navigator.grid.seen))
        candidate = self.goal_xy if self.goal_is_candidate else None
        distance = math.inf if candidate is None else self.navigator.distance_to(candidate)
        if (self.progress is not None and candidate is not None
                and not np.array_equal(candidate, self.progress[3])):
            previous = self.progress[3]
            fresh = previous is None or self.navigator.candidate_viewed(previous)
            self.progress = (self.progress[0], now_s if fresh else self.progress[1], distance,
                             candidate)
        if (self.progress is None or covered >= self.progress[0] + STALL_CELLS
                or (candidate is not None and distance <= self.progress[2] - STALL_APPROACH_M)):
            self.progress = (covered, now_s, distance, candidate)
        elif elapsed_s(now_s, self.progress[1]) > STALL_S:
            if self.goal_xy is not None:
                self.navigator.give_up_on(self.goal_xy)
            self.goal_xy = None
            self.progress = (covered, now_s, math.inf, None)

    def _note_approach_progress(self, now_s: float) -> None:
        """APPROACH and LOST switch between their usual way to the can (the direct law while
        the straight line is clear, else a grid path; LOST when the can leaves the view) and
        keeping to the grid path (the can leaving the view is no reason to stop following it)
        whenever in ``~obstacle_memory`` + ``APPROACH_STALL_BEYOND_MEMORY_S`` they have brought
        the robot no ``STALL_APPROACH_M`` nearer to it while it is farther than
        ``DIRECT_GAP_M``. A way that ends in a cycle (an obstacle's corner beside the straight
        line: the path around it turns the camera away from the can, LOST turns back, the
        direct law meets the corner again) or in standing gives way to the other."""
        if (self.state not in (State.APPROACH, State.LOST) or self.can_xy is None
                or self.navigator.pose is None):
            return
        distance = self.navigator.distance_to(self.can_xy)
        stall_s = self.config.obstacle_memory + APPROACH_STALL_BEYOND_MEMORY_S
        if (self.approach_progress is None
                or distance <= self.approach_progress[0] - STALL_APPROACH_M
                or not self._beyond_direct_gap()):
            self.approach_progress = (distance, now_s)
        elif elapsed_s(now_s, self.approach_progress[1]) > stall_s:
            self.keep_to_path = not self.keep_to_path
            self.approach_progress = (distance, now_s)
            self.path_xy = None
            self._because('no %.1f m nearer to the can in %.0f s: %s' % (
                STALL_APPROACH_M, stall_s,
                'keeping to a path to it' if self.keep_to_path else 'taking the direct way '
                'again where the straight line is clear'))

    def command(self, now_s: float) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) command to send at ``now_s``.

        Raises when the tick fails (ValueError for a non-finite command); the node then sends
        zero, so the controller counts the tick as a zero: the next command starts from rest
        within the acceleration limits.
        """
        try:
            return self._command(now_s)
        except Exception as error:
            self.last_command = (0.0, 0.0)
            self.why = 'control tick failed (%s: %s)' % (type(error).__name__, error)
            raise

    def _command(self, now_s: float) -> Tuple[float, float]:
        dt_s = 0.0 if self.last_command_s is None else elapsed_s(now_s, self.last_command_s)
        self.last_command_s = now_s
        self.why = ''
        if not self.enabled:
            # A disarm is an emergency stop: zero at once, not a ramp-down within the
            # acceleration limits that would keep the robot driving after it was told to stop.
            self.last_command = (0.0, 0.0)
            self.why = self._disarmed_reason()
            return self.last_command
        if self.is_stale(now_s):
            self.last_command = (0.0, 0.0)
            self.why = problems_text(self.missing_inputs(now_s))
            return self.last_command
        if (self.state is State.LOST
                and elapsed_s(now_s, self.lost_since_s) > self.config.lost_timeout):
            self._enter(State.SEARCH)
        recovery = self.bump.command(self.navigator.pose, now_s)
        if recovery is not None:
            self._because(recovery[1])
            desired = recovery[0]
            self.path_xy = None
        else:
            desired = require_finite(self.desired(now_s), '%s command' % self.state.value)
            desired = self._safe(desired, now_s, look=True)
        linear, angular = self._safe(limit_twist(self.last_command, desired, dt_s, self.limits),
                                     now_s)
        self._note_progress(now_s)
        self._note_approach_progress(now_s)
        # Never forward while closer than stop_distance, even if braking exceeds the limit.
        if (self.state is not State.WANDER and self.sighting is not None
                and self.sighting.has_range and linear > 0.0):
            if self.sighting.gap_m < self.config.stop_distance:
                linear = 0.0
                self._because('closer than stop_distance (gap %.3f m): no driving forward'
                              % self.sighting.gap_m)
        self.last_command = (linear, angular)
        if self.state is State.APPROACH and self._settled(self.last_command):
            if self._can_vouched_for(now_s):
                self._enter(State.STOPPED)
                self.seen_since_stop_s = now_s
            else:
                self._enter(State.LOST)
                self.lost_since_s = now_s
                self.why = ('arrived where the can was ranged last, but the camera has not '
                            'seen it there for %.1f s: LOST'
                            % elapsed_s(now_s, self.ranged_seen_s))
        return self.last_command

    def _can_vouched_for(self, now_s: float) -> bool:
        """True when the camera ranged the can within ~vanish_timeout, or the can is below its
        view: only then is an approach that arrived at the can, not at a place a false or
        stale estimate put it (a can carried on odometry for long, or one frame that ranged a
        half-hidden can far away)."""
        return (elapsed_s(now_s, self.ranged_seen_s) <= self.config.vanish_timeout
                or self.can_below_view())
