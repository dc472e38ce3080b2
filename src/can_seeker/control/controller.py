"""Stop-near-can controller: search for the can, drive to it, stop just in front of it.

:class:`Controller` is pure (no rospy), a facade over the parts in this package: the
``can_stopper`` node feeds it detections, odometry, range scans and the camera's view of the
floor, and asks it for a command (linear m/s, angular rad/s in base_link) at a fixed rate or,
in lockstep, once per frame. The parts: input freshness (:mod:`.input_freshness`), which
detection is the can (:mod:`.can_tracker`), the states and their one transition table
(:mod:`.supervisor`), a behaviour per state (:mod:`.behaviours`), recoveries
(:mod:`.recoveries`, :mod:`.bump_recovery`), the stateless safety filter (:mod:`.safety_filter`)
and the tick that runs them in order (:mod:`.tick`). Geometry (REP-103): a detection gives the
range from the camera to the can's near surface and the bearing; the gap is measured from the
robot front (a circle of ``robot_radius`` about base_link) to that surface.

IDLE: disarmed (``~enabled`` false, or :meth:`Controller.set_enabled` false), every command
zero; arming starts afresh with an empty map. A stale detection gives zero; a stale scan,
odometry or camera_info allows turning only; a non-finite command is an error, never a limit.
:attr:`Controller.reason` says why a command is zero or limited (:attr:`Controller.why` in
words), and :meth:`Controller.missing_inputs` names the missing or stale inputs.

Design, reasons and limits: docs/design/controller-and-safety.md.
"""
import math
from typing import List, Optional, Tuple

import numpy as np

from can_seeker.frames import BASE_FRAME, ODOM_FRAME
from can_seeker.health import ERROR, OK, WARN, Health
from can_seeker.params import Param
from can_seeker.control.input_freshness import MissingInput, problems_text
from can_seeker.control.navigation import CameraView, Pose2D
from can_seeker.control.parts import ControllerParts
from can_seeker.control.reasons import Kind, Reason, reason
from can_seeker.control.sighting import Sighting
from can_seeker.control.supervisor import Event, State
from can_seeker.control.twist_limits import ZERO

PARAMS = (
    Param('enabled', True, 'start armed: searching and driving; false starts IDLE (zero '
          'commands) until the ~enable service arms it'),
    Param('explore', True, 'explore the room when a full turn in place did not show the can; '
          'false keeps the robot turning in place to search (it still drives to a can it '
          'sees)'),
    Param('behaviour', 'seek',
          'seek: search, explore, approach the can and stop; wander: drive around and turn '
          'away from obstacles, no can', choices=('seek', 'wander')),
    Param('bumper_topic', '', 'std_msgs/Bool contact sensor (true: the bumper is pressed): '
          'stop, back off, keep off the contact; empty: no bumper'),
    Param('scan_topics', 'camera_scan',
          'sensor_msgs/LaserScan topics of obstacles, separated by spaces (camera scan, lidar, '
          'both: what any of them sees is an obstacle; any frame in TF); empty: no obstacle '
          'sensing, no exploration'),
    Param('odom_topic', 'odom', 'nav_msgs/Odometry of the robot in ~odom_frame'),
    BASE_FRAME,
    ODOM_FRAME,
    Param('lockstep', False, 'answer every detection at once with a command stamped like its '
          'image (on /cmd_vel and cmd_vel_stamped; for a simulator in lockstep); the timer then '
          'sends only the zero of a stale detection'),
    Param('rate', 20.0, 'rate of the /cmd_vel commands from the control timer (Hz)', 1.0, 200.0),
    Param('input_timeout', 0.5,
          'zero Twist while the newest detection shows an image older than this, by its header '
          'stamp (by its arrival when stamped later); no scan for this long, or no camera_info '
          'for twice this long with obstacle sensing: no driving forward or back, only turning; '
          'no odometry for this long: no exploring or path driving (s)', 0.05, 10.0,
          safer='lower'),
    Param('stop_distance', 0.25,
          'gap between the robot front and the can near surface when stopped (m)', 0.02, 3.0,
          safer='higher'),
    Param('max_linear', 0.4, 'forward speed limit; exploring cruises at 0.3 m/s, or at this '
          'when it is lower (m/s)', 0.01, 2.0, safer='lower'),
    Param('max_reverse', 0.1, 'backing-up speed limit: when closer than stop_distance, and '
          'to see floor below the camera\'s view that keeps the robot from driving (m/s)',
          0.0, 1.0, safer='lower'),
    Param('max_angular', 1.2, 'turn rate limit (rad/s)', 0.05, 6.0, safer='lower'),
    Param('max_linear_accel', 0.5, 'linear acceleration and deceleration limit (m/s^2)',
          0.05, 5.0, safer='lower'),
    Param('max_angular_accel', 3.0, 'angular acceleration limit (rad/s^2)', 0.1, 20.0,
          safer='lower'),
    Param('robot_radius', 0.165, 'radius of the robot body about base_link (m)', 0.0, 2.0,
          safer='higher'),
    Param('safety_margin', 0.05, 'clearance the safety layer keeps from any sensed obstacle, '
          'beyond robot_radius (m)', 0.0, 1.0, safer='higher'),
    Param('wander_clearance', 0.5, 'WANDER turns away when less free travel than this lies '
          'ahead (m)', 0.05, 5.0),
)
"""The can_stopper parameters: the robot's figures, frames, topics and sensors; the control
law's own heuristics are the constants of :mod:`can_seeker.control.tuning`."""


def control_health(state: State, enabled: bool, why: str, last_command: Tuple[float, float],
                   missing: List[MissingInput], bumps: int) -> Health:
    """The control status for /diagnostics: ERROR while an input is overdue (WARN while one is
    awaited after a reset, or while disarmed: nothing drives then), and the state with why its
    last command is zero or limited, or what it commands."""
    linear, angular = last_command
    doing = why or 'commanding %.2f m/s, %.2f rad/s' % (linear, angular)
    values = (('state', state.value), ('armed', 'yes' if enabled else 'no'),
              ('linear (m/s)', '%.3f' % linear), ('angular (rad/s)', '%.3f' % angular),
              ('why', why or 'none'), ('missing inputs', problems_text(missing) or 'none'),
              ('bumps', str(bumps)))
    level = ERROR if any(item.overdue for item in missing) else WARN if missing else OK
    if not enabled:
        level = min(level, WARN)
    return Health(level, '%s: %s' % (state.value, doing), values)


class Controller:
    """The controller's public interface (times are seconds on one clock, sim time in the
    node): :meth:`observe` every detection message (found or not), :meth:`observe_pose`
    odometry, :meth:`observe_scan` range scans; :meth:`command` at the control rate."""

    def __init__(self, config, camera_info_topic: str = 'camera_info',
                 arm_hint: str = 'call the enable service with true'):
        """``config``: :func:`~can_seeker.control.tuning.controller_settings` of :data:`PARAMS`;
        ``camera_info_topic`` names that input when missing; ``arm_hint``: how to arm the node."""
        self.config, self.arm_hint, self.enabled = config, arm_hint, bool(config.enabled)
        self.parts = parts = ControllerParts(config, camera_info_topic)
        self.wander, self.scan_sources = parts.wander, parts.scan_sources
        self.senses_obstacles = bool(self.scan_sources)
        self.navigator, self.inputs, self.tracker = parts.navigator, parts.inputs, parts.tracker
        self.context, self.supervisor, self.tick = parts.context, parts.supervisor, parts.tick
        self.reset()

    state = property(lambda self: self.supervisor.state, doc='The current :class:`State`.')
    why = property(lambda self: '' if self.reason is None else self.reason.text,
                   doc='Why the last command was zero or limited, in words (\'\': it was not).')
    last_command = property(lambda self: self.context.last_command, doc='The last command.')
    sighting = property(lambda self: self.tracker.sighting, doc='The can now, or None.')
    can_xy = property(lambda self: self.tracker.can_xy, doc='Where the can was ranged (odom).')
    path_xy = property(lambda self: self.context.paths.path_xy, doc='The path (odom) or None.')
    needs_camera_info = property(lambda self: self.inputs.needs_camera_info,
                                 doc='True when driving depends on the camera\'s view.')

    def reset(self, now_s: float = -math.inf) -> None:
        """Back to SEARCH (IDLE while disarmed, WANDER to wander) at rest, with no detection
        seen yet and an empty map; detections of images taken before ``now_s`` and
        camera_info that came before are ignored."""
        self.inputs.reset(now_s)
        self.supervisor.handle(Event.RESET_DISARMED if not self.enabled else
                               Event.RESET_WANDER if self.wander else Event.RESET_SEEK, now_s)
        self.parts.bump.cancel()
        self.tracker.reset()
        self.context.paths.reset()
        self.tick.reset()
        self.navigator.reset()
        self.reason: Optional[Reason] = None if self.enabled else self._disarmed

    def observe(self, sighting: Optional[Sighting], now_s: float,
                image_stamp_s: float = math.inf) -> None:
        """One detection message received at ``now_s`` of an image taken at ``image_stamp_s``
        (as fresh as its image, never fresher than its arrival); ``sighting``: its red object
        (None: none), the can by its confidence (:meth:`CanTracker.shows_can`)."""
        if image_stamp_s < self.inputs.ignore_before_s or self.wander:
            return
        self.inputs.last_image_s = stamp_s = min(now_s, image_stamp_s)
        tracking = self.state in (State.APPROACH, State.STOPPED)
        ranged = self.tracker.observe(sighting, stamp_s, tracking)
        if self.context.camera_view is not None:
            self.navigator.mark_seen(self.context.camera_view)
        if not ranged and tracking and (self.tracker.below_view(self.context.camera_view)
                                        or self.parts.approach.stop_aside.chosen
                                        or self.parts.keep_to_path.keeping()):
            # The camera cannot range the can there, or the can left the view while the robot
            # heads for a stop point aside or keeps to a path: go on with where it was ranged.
            self.tracker.carry()
            ranged = True
        self.supervisor.handle(self.supervisor.behaviour.on_detection(ranged, now_s), now_s)

    def observe_pose(self, pose: Pose2D, now_s: float, stamp_s: Optional[float] = None) -> None:
        """Odometry: base_link's pose in odom received at ``now_s``, stamped ``stamp_s``
        (default: ``now_s``)."""
        if self.navigator.pose is not None:
            self.supervisor.behaviour.on_pose(self.navigator.pose, pose)
        self.navigator.pose = pose
        self.inputs.pose_s = now_s
        self.tracker.observe_pose(pose, now_s if stamp_s is None else stamp_s)

    def observe_scan(self, source: str, ends_base: np.ndarray, hits: np.ndarray, origin_base,
                     now_s: float, range_min_m: float = 0.0, stamp_s: float = math.inf):
        """A range scan of ``source`` (one of the ``scan_topics``) in base_link received at
        ``now_s``, taken at ``stamp_s``: placed in odom from the pose then (never later than
        its arrival; :meth:`Navigator.add_scan`)."""
        if self.navigator.pose is None:
            return
        pose = self.tracker.poses.at(min(now_s, stamp_s)) or self.navigator.pose
        self.navigator.add_scan(ends_base, hits, origin_base, pose, range_min_m, now_s, source)
        self.inputs.scan_s[source] = now_s

    def set_camera_view(self, view: CameraView) -> None:
        """The camera's floor footprint in base_link, for coverage."""
        self.context.camera_view = view

    def observe_camera_info(self, now_s: float) -> None:
        self.inputs.camera_info_s = now_s  # a usable camera_info (the view's intrinsics)

    def set_enabled(self, enabled: bool, now_s: float) -> str:
        """Arm (afresh, as :meth:`reset`) or disarm (IDLE: every command zero from this call
        on); returns what was done, in a sentence."""
        if enabled == self.enabled:
            return 'already %s' % ('armed' if enabled else 'disarmed')
        self.enabled = enabled
        self.reset(now_s)
        return ('armed: %s' % self.state.value if enabled else
                'disarmed: zero commands until armed again')

    def observe_bump(self, pressed: bool, now_s: float) -> bool:
        """A bumper message at ``now_s``; True for a new touch while armed: the robot stops at
        once (the node sends zero now), the contact stays in the map, the back-off starts."""
        if not self.enabled:
            self.parts.bump.pressed = pressed
            return False
        was_pressed = self.parts.bump.pressed
        contact = self.parts.bump.bumped(pressed, self.navigator.pose, now_s)
        if not pressed or was_pressed:
            return False
        if contact is not None:
            self.navigator.world.add_contact(contact)
        self.context.paths.clear()
        self.context.last_command = ZERO
        return True

    def command(self, now_s: float) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) command at ``now_s``. Raises when the tick fails
        (ValueError for a non-finite command); it then counts as a zero (the node sends zero)."""
        try:
            command, self.reason = self.tick.run(now_s, None if self.enabled else self._disarmed)
            return command
        except Exception as error:
            self.context.last_command = ZERO
            self.reason = reason(Kind.TICK_FAILED, error=type(error).__name__, message=str(error))
            raise

    def detection_stale(self, now_s: float) -> bool:
        """True when a detection came since the reset and is stale by the next tick."""
        return self.inputs.is_stale(now_s) and self.inputs.last_image_s is not None

    def missing_inputs(self, now_s: float) -> List[MissingInput]:
        """The missing or stale inputs that keep the robot from driving."""
        return self.inputs.missing_inputs(now_s)

    def health(self, now_s: float, why: Optional[str] = None) -> Health:
        """:func:`control_health` now (``why``: instead of :attr:`why`)."""
        return control_health(self.state, self.enabled, self.why if why is None else why,
                              self.last_command, self.missing_inputs(now_s), self.parts.bump.count)

    def map_layers(self, obstacles: bool = False):
        """The coverage grid's values (with ``obstacles``: the obstacle memory's) with the
        cell size and the grid's origin (m, odom), for OccupancyGrid messages."""
        world = self.navigator.world
        values = world.obstacle_values() if obstacles else world.coverage_values()
        return values, world.resolution_m, world.origin_m

    _disarmed = property(lambda self: reason(Kind.DISARMED, arm_hint=self.arm_hint))
    robot_xy = property(lambda self: None if self.navigator.pose is None else (
        self.navigator.pose.x, self.navigator.pose.y), doc='The robot in odom, or None.')
