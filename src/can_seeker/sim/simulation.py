"""The simulator's parameters, the scene they describe, and its sim-time loop: commands in,
physics steps, frames, scans and contacts out.

Time is counted in physics steps (exact sim time, no float drift). Each step applies the
acceleration-limited twist of the freshest command (zero once it is older than the timeout),
steps pybullet once, and says whether a camera frame, a scan and a state message are due.
"""
import math
import os
import random
from dataclasses import dataclass, replace
from types import SimpleNamespace
from typing import Callable, FrozenSet, Optional, Sequence, Tuple

import numpy as np
import yaml

from can_seeker.camera_geometry import camera_pose_from_mount
from can_seeker.camera_mount import CAMERA_FORWARD_M, MOUNT_PARAMS, CameraMount, random_mount
from can_seeker.sim.drive import CommandWatchdog, TwistLimiter
from can_seeker.frames import SIM_FRAME_PARAMS
from can_seeker.params import Param
from can_seeker.robot_profile import ProfileError, load_profile
from can_seeker.sim.appearance import random_appearance
from can_seeker.sim.lidar import LidarSpec
from can_seeker.sim.realism import (PRESETS, REALISM_PARAMS, Realism, spec_from_config,
                                    trial_key)
from can_seeker.sim.scene import (CAN_CLEARANCE_M, CAN_RADIUS_M, OBSTACLE_RGBA, ROBOT_RADIUS_M,
                                  WALL_RGBA, Scene, can_visible, empty_bounds,
                                  random_can_position, random_free_can_position,
                                  random_obstacles, room_walls, scene_from_dict)
from can_seeker.sim.world import CAN_RGBA, CAN_TEXTURES, RENDERERS, CameraSpec, World


def _rgba_text(rgba: Sequence[float]) -> str:
    return ' '.join('%g' % channel for channel in rgba)


DEFAULT_CAN_RGBA = _rgba_text(CAN_RGBA)
WORLDS = ('empty', 'room')
"""Built-in worlds; any other ~world value is a world file."""

PARAMS = (
    Param('gui', False, 'open the pybullet GUI; only when the X display can be opened, '
          'headless with a warning otherwise'),
    Param('renderer', 'auto', 'camera renderer: auto (EGL, TinyRenderer if EGL fails), egl or '
          'tiny', choices=RENDERERS),
    Param('width', 320, 'image width (px)', 16, 4096),
    Param('height', 240, 'image height (px)', 16, 4096),
    Param('fov_deg', 45.0, 'vertical field of view (deg)', 10.0, 120.0),
    Param('encoding', 'bgr8', 'image encoding of /camera/image_raw', choices=('bgr8', 'rgb8')),
    Param('camera_rate', 15.0, 'camera frame rate (Hz, sim time)', 0.1, 240.0),
    *MOUNT_PARAMS,
    Param('robot', '', 'robot profile (a name in the package\'s config/robots/ or a YAML path) '
          'the robot is built from: body, wheels, camera mount and field of view, lidar; it '
          'replaces ~camera_height, ~camera_pitch_deg, ~fov_deg and the ~scan_ rate, beams, '
          'ranges and height (a profile without a lidar turns it off); empty: the built-in '
          'robot (config/robots/default.yaml) with those parameters'),
    Param('physics_rate', 240.0, 'physics steps per second of sim time (Hz); /clock ticks at '
          'every step unless ~clock_rate is set', 60.0, 2000.0),
    Param('clock_rate', 0.0, 'rate of /clock (Hz, sim time; 0: at every physics step); /clock '
          'also ticks at every step that publishes a frame, a scan or the state, so no message '
          'is stamped ahead of it', 0.0, 2000.0),
    Param('state_rate', 50.0, 'rate of /odom, TF odom->base_link, /sim/can_pose and /sim/contact '
          '(Hz, sim time)', 1.0, 1000.0),
    Param('real_time_factor', 1.0, 'sim seconds per wall-clock second; 0 runs as fast as '
          'possible', 0.0, 1000.0),
    Param('cmd_timeout', 0.5, 'brake to a stop when the last /cmd_vel is older than this '
          '(s, sim time)', 0.01, 60.0),
    Param('max_linear_accel', 1.0, 'linear acceleration limit of the base (m/s^2)', 0.01, 20.0),
    Param('max_angular_accel', 4.0, 'angular acceleration limit of the base (rad/s^2)',
          0.01, 100.0),
    Param('can_placement', 'random', 'random: in the empty world the can centre is at a '
          'random bearing and distance in [~can_min_distance, ~can_max_distance] from the robot '
          'start, elsewhere anywhere in free space (0.4 m clear of walls and obstacles, at '
          'least ~can_min_distance away) unless the world file places it; drawn from ~seed. '
          'fixed: at (~can_x, ~can_y)', choices=('random', 'fixed')),
    Param('can_x', 1.0, 'can centre x in odom when ~can_placement is fixed (m)', -100.0, 100.0),
    Param('can_y', 0.0, 'can centre y in odom when ~can_placement is fixed (m)', -100.0, 100.0),
    Param('world', 'empty', 'empty (a floor), room (walls around ~room_length x ~room_width '
          'with ~obstacles random obstacles) or a YAML world file: a path, or a file name in '
          'the package\'s worlds/ folder'),
    Param('room_length', 6.0, 'inside length of the room along x, centred on the robot start '
          '(m)', 2.0, 100.0),
    Param('room_width', 6.0, 'inside width of the room along y, centred on the robot start (m)',
          2.0, 100.0),
    Param('obstacles', 6, 'number of random boxes and cylinders (sides 0.1-0.5 m, 0.15-0.5 m '
          'tall) in the room, drawn from ~seed', 0, 100),
    Param('floor_rgba', '', 'floor colour: red green blue alpha in 0-1; empty: pybullet\'s '
          'blue and white checker floor'),
    Param('wall_rgba', _rgba_text(WALL_RGBA), 'wall colour: red green blue alpha in 0-1'),
    Param('obstacle_rgba', _rgba_text(OBSTACLE_RGBA), 'obstacle colour: red green blue alpha '
          'in 0-1 (a world file may colour each obstacle)'),
    Param('randomize_appearance', False, 'draw the floor (pybullet\'s checker, one colour or a '
          'checker of two), wall and obstacle colours from the seed of each world (~seed, '
          '/sim/new_world) instead of ~floor_rgba, ~wall_rgba and ~obstacle_rgba: light and '
          'dark, some hardly standing out from the floor, never red; a world file\'s colours '
          'still win'),
    Param('randomize_mount', False, 'draw the camera mount of each world from its seed (~seed, '
          '/sim/new_world): height 0.15-0.35 m, pitch 15-35 deg down, instead of '
          '~camera_height and ~camera_pitch_deg; TF base_link -> camera_link follows (the '
          'robot model on robot_description keeps the parameters\' mount)'),
    Param('scan_rate', 10.0, 'rate of the simulated lidar /scan (Hz, sim time); 0 turns it '
          'off', 0.0, 240.0),
    Param('scan_beams', 360, 'beams of the lidar over 360 deg', 8, 4096),
    Param('scan_range_min', 0.12, 'nearest range the lidar reports (m)', 0.0, 1.0),
    Param('scan_range_max', 8.0, 'farthest range the lidar reports; beyond it a beam reads '
          'inf (m)', 0.5, 100.0),
    Param('scan_height', 0.1, 'height of the lidar beams (frame base_scan) above base_link '
          '(m)', 0.09, 2.0),
    Param('seed', 0, 'random seed of the can placement and the room\'s obstacles',
          0, 2 ** 31 - 1),
    Param('can_min_distance', 0.5, 'nearest random can centre from the robot start (m)',
          0.3, 50.0),
    Param('can_max_distance', 3.0, 'farthest random can centre from the robot start (m)',
          0.3, 50.0),
    Param('can_rgba', DEFAULT_CAN_RGBA, 'can colour: red green blue alpha, four numbers in 0-1'),
    Param('can_texture', 'textured', 'textured: a soda can with a label (body in ~can_rgba, a '
          'band of white lettering-like marks, silver lid and base); plain: one colour all over',
          choices=CAN_TEXTURES),
    Param('lockstep', False, 'after each camera frame, step no further until every '
          '~lockstep_topics topic and the stamped command (cmd_vel_stamped) answered it with a '
          'message stamped at or after the frame (or ~lockstep_timeout passed); the base then '
          'follows cmd_vel_stamped only'),
    Param('lockstep_topics', 'image_converter/detection', 'topics with a std_msgs/Header '
          'whose stamp must reach the frame stamp before the next step in lockstep, separated '
          'by spaces; a topic without a publisher is not waited for'),
    Param('lockstep_timeout', 2.0, 'wall-clock seconds a frame waits for its answers in '
          'lockstep before the simulation steps on (counted, with a warning)', 0.01, 600.0),
) + SIM_FRAME_PARAMS + REALISM_PARAMS

MIN_CAN_CLEARANCE_M = ROBOT_RADIUS_M + CAN_RADIUS_M
"""A can centre closer than this to base_link (m) would overlap the robot."""


def parse_rgba(text: str) -> Tuple[float, float, float, float]:
    """Four numbers in 0-1 separated by spaces or commas; ValueError otherwise."""
    try:
        values = tuple(float(part) for part in text.replace(',', ' ').split())
    except ValueError:
        raise ValueError('expected four numbers, got %r' % (text,))
    if len(values) != 4 or not all(0.0 <= value <= 1.0 for value in values):
        raise ValueError('expected four numbers in 0-1, got %r' % (text,))
    return values


def _checked_colour(config: SimpleNamespace, name: str, warn: Callable[[str], None],
                    allow_empty: bool = False) -> Optional[Tuple[float, float, float, float]]:
    """The parsed colour parameter ``name`` (None when empty is allowed and given); a bad value
    is warned and replaced by the default."""
    text = getattr(config, name)
    if allow_empty and not text.strip():
        return None
    try:
        return parse_rgba(text)
    except ValueError as error:
        default = {spec.name: spec.default for spec in PARAMS}[name]
        warn('parameter ~%s: %s; using the default %r' % (name, error, default))
        setattr(config, name, default)
        return _checked_colour(config, name, warn, allow_empty)


def world_file_path(world: str, search_dirs: Sequence[str]) -> str:
    """The world file ``world`` names: an existing path, or a file in one of ``search_dirs``
    (the .yaml suffix may be left out); ValueError if there is none."""
    candidates = [world] + [os.path.join(folder, name) for folder in search_dirs
                            for name in (world, world + '.yaml')]
    for candidate in candidates:
        if os.path.isfile(candidate):
            return candidate
    raise ValueError('no world file %r (looked in %s)'
                     % (world, ', '.join(search_dirs) or 'the current directory'))


def load_world_file(path: str) -> dict:
    """The mapping in a YAML world file (checked by :func:`scene_for`); ValueError if unreadable."""
    try:
        with open(path) as stream:
            data = yaml.safe_load(stream)
    except (OSError, yaml.YAMLError) as error:
        raise ValueError('cannot read world file %s: %s' % (path, error))
    scene_from_dict(data)
    return data


def apply_profile(config: SimpleNamespace, warn: Callable[[str], None],
                  robot_dirs: Sequence[str] = ()):
    """Set ``profile`` (the ``~robot`` profile, or None), ``camera_forward``, ``scan_field_deg``
    and ``robot_radius`` on ``config``; a profile's camera and lidar replace the parameters'."""
    config.profile, config.camera_forward, config.scan_field_deg = None, CAMERA_FORWARD_M, 360.0
    config.robot_radius = ROBOT_RADIUS_M
    if not config.robot:
        return
    try:
        profile = load_profile(config.robot, robot_dirs)
    except ProfileError as error:
        warn('parameter ~robot: %s; using the built-in robot' % error)
        return
    config.profile, config.robot_radius = profile, profile.body_radius_m
    camera = profile.camera
    config.camera_height, config.camera_pitch_deg = camera.height_m, camera.pitch_deg
    config.camera_forward, config.fov_deg = camera.forward_m, camera.vertical_fov_deg
    lidar = profile.lidar
    if lidar is None:
        config.scan_rate = 0.0
        return
    config.scan_rate, config.scan_beams = lidar.rate_hz, lidar.beams
    config.scan_range_min, config.scan_range_max = lidar.range_min_m, lidar.range_max_m
    config.scan_height, config.scan_field_deg = lidar.height_m, lidar.field_deg


def checked_config(params: SimpleNamespace, warn: Callable[[str], None],
                   world_dirs: Sequence[str] = (),
                   robot_dirs: Sequence[str] = ()) -> SimpleNamespace:
    """``params`` with the checks that span parameters applied: bad values warned and replaced.

    Adds ``can_color``, ``floor_color``, ``wall_color``, ``obstacle_color`` (parsed colours),
    ``world_data`` (the world file's mapping, or None), ``scene`` (the world at ~seed) and
    ``can_position`` (where the can starts), and the robot profile's (:func:`apply_profile`).
    World files are looked up in ``world_dirs``, robot profiles in ``robot_dirs``.
    """
    config = SimpleNamespace(**vars(params))
    apply_profile(config, warn, robot_dirs)
    config.can_color = _checked_colour(config, 'can_rgba', warn)
    config.floor_color = _checked_colour(config, 'floor_rgba', warn, allow_empty=True)
    config.wall_color = _checked_colour(config, 'wall_rgba', warn)
    config.obstacle_color = _checked_colour(config, 'obstacle_rgba', warn)
    for name in ('camera_rate', 'state_rate', 'scan_rate', 'clock_rate'):
        if getattr(config, name) > config.physics_rate:
            warn('~%s %r is above ~physics_rate %r; using %r'
                 % (name, getattr(config, name), config.physics_rate, config.physics_rate))
            setattr(config, name, config.physics_rate)
    if config.lockstep and config.scan_rate > 0.0:
        config.scan_rate = _whole_step_rate(config.scan_rate, config.physics_rate, warn)
    if config.can_max_distance < config.can_min_distance:
        warn('~can_max_distance %r is below ~can_min_distance %r; using %r for both'
             % (config.can_max_distance, config.can_min_distance, config.can_min_distance))
        config.can_max_distance = config.can_min_distance
    if config.scan_range_max <= config.scan_range_min:
        warn('~scan_range_max %r is not above ~scan_range_min %r; using %r'
             % (config.scan_range_max, config.scan_range_min, config.scan_range_min + 1.0))
        config.scan_range_max = config.scan_range_min + 1.0
    if config.can_placement == 'fixed' and (math.hypot(config.can_x, config.can_y)
                                            < MIN_CAN_CLEARANCE_M):
        defaults = {spec.name: spec.default for spec in PARAMS}
        warn('(~can_x, ~can_y) = %r overlaps the robot; placing the can at %r'
             % ((config.can_x, config.can_y), (defaults['can_x'], defaults['can_y'])))
        config.can_x, config.can_y = defaults['can_x'], defaults['can_y']
    config.world_data = None
    if config.world not in WORLDS:
        try:
            config.world_data = load_world_file(world_file_path(config.world, world_dirs))
        except ValueError as error:
            warn('parameter ~world: %s; using the empty world' % error)
            config.world = 'empty'
    config.scene = scene_for(config, config.seed, warn)
    config.can_position = config.scene.can_xy
    return config


def _whole_step_rate(rate_hz: float, physics_rate_hz: float,
                     warn: Callable[[str], None]) -> float:
    """The lidar rate in lockstep: a whole number of physics steps per scan, so every scan
    comes exactly one scan_time after the previous one (a controller in lockstep waits for the
    scans due by each frame from that period); another rate is warned about and rounded."""
    steps = physics_rate_hz / rate_hz
    if abs(steps - round(steps)) < 1e-6:
        return rate_hz
    whole_rate_hz = physics_rate_hz / max(1, round(steps))
    warn('~scan_rate %r Hz is %.3f physics steps per scan; in lockstep a scan comes every '
         'whole number of steps: using %r Hz' % (rate_hz, steps, whole_rate_hz))
    return whole_rate_hz


def scene_for(config: SimpleNamespace, seed: int, warn: Callable[[str], None]) -> Scene:
    """The world a :func:`checked_config` describes, with its random parts drawn from ``seed``:
    the room's obstacles first (clear of the start and of a fixed can), then the can; with
    ``randomize_appearance`` the colours too (from a stream of their own: the geometry is the
    same either way)."""
    if config.randomize_appearance:
        look = random_appearance(seed)
        colours = {'floor_rgba': look.floor_rgba, 'floor_checker_rgba': look.floor_checker_rgba,
                   'wall_rgba': look.wall_rgba, 'obstacle_rgba': look.obstacle_rgba}
    else:
        colours = {'floor_rgba': config.floor_color, 'wall_rgba': config.wall_color,
                   'obstacle_rgba': config.obstacle_color}
    generator = random.Random(seed)
    fixed_can = (config.can_x, config.can_y) if config.can_placement == 'fixed' else None
    if config.world == 'room':
        bounds = (-config.room_length / 2.0, config.room_length / 2.0,
                  -config.room_width / 2.0, config.room_width / 2.0)
        keep_clear = [] if fixed_can is None else [(fixed_can, CAN_RADIUS_M + CAN_CLEARANCE_M)]
        obstacles = random_obstacles(generator, config.obstacles, bounds, keep_clear)
        if len(obstacles) < config.obstacles:
            warn('only %d of %d obstacles fit into the room' % (len(obstacles), config.obstacles))
        scene = Scene(bounds, room_walls(config.room_length, config.room_width), obstacles,
                      **colours)
    elif config.world_data is not None:
        scene = scene_from_dict(config.world_data, **colours)
    else:
        scene = Scene(empty_bounds(), **colours)
    if fixed_can is not None:
        problem = scene.can_place_problem(*fixed_can)
        if problem is None:
            return scene.with_can(fixed_can)
        warn('(~can_x, ~can_y): %s; placing the can at random' % problem)
    if scene.can_xy is not None:
        return scene
    if not scene.solids:
        return scene.with_can(random_can_position(seed, config.can_min_distance,
                                                  config.can_max_distance))
    try:
        return scene.with_can(random_free_can_position(generator, scene,
                                                       config.can_min_distance,
                                                       robot_radius_m=config.robot_radius))
    except ValueError as error:
        warn('%s; removing the obstacles' % error)
    scene = Scene(scene.bounds, scene.walls, (), **colours)
    try:
        return scene.with_can(random_free_can_position(generator, scene,
                                                       config.can_min_distance,
                                                       robot_radius_m=config.robot_radius))
    except ValueError as error:
        warn('%s even without obstacles; using the empty world' % error)
    return Scene(empty_bounds(), **colours).with_can(random_can_position(
        seed, config.can_min_distance, config.can_max_distance))


def can_visible_from_start(scene: Scene, camera: CameraSpec) -> bool:
    """Whether the can of ``scene`` is in view, unoccluded, of ``camera`` on a robot at the
    start pose."""
    return can_visible(scene, camera_pose_from_mount(camera.mount), camera.intrinsics)


def camera_spec(config: SimpleNamespace) -> CameraSpec:
    """The camera described by the parameters (the mount of ``~seed``'s world when
    ``randomize_mount``)."""
    return CameraSpec(config.width, config.height, config.fov_deg, mount_for(config, config.seed))


def mount_for(config: SimpleNamespace, seed: int) -> CameraMount:
    """The camera mount of the world of ``seed``: drawn from it when ``randomize_mount``, else
    the parameters' one."""
    forward_m = getattr(config, 'camera_forward', CAMERA_FORWARD_M)
    if config.randomize_mount:
        return replace(random_mount(seed), forward_m=forward_m)
    return CameraMount(config.camera_height, config.camera_pitch_deg, forward_m)


class RateSchedule:
    """Says at which physics steps an event of ``rate_hz`` is due: the first one period after
    the start step (0, or the last :meth:`restart`), then at the first step at or after each
    multiple of the period from there (no drift)."""

    def __init__(self, rate_hz: float, physics_rate_hz: float):
        self._steps_per_event = physics_rate_hz / rate_hz
        self.restart(0)

    def restart(self, step: int) -> None:
        """Count the periods from ``step``: the next event is one period after it."""
        self._start_step = step
        self._next_event = 1

    def due(self, step: int) -> bool:
        """Whether the event is due at ``step``; call once per step, in order."""
        elapsed = step - self._start_step
        if elapsed + 1e-9 < self._next_event * self._steps_per_event:
            return False
        self._next_event = math.floor(elapsed / self._steps_per_event + 1e-9) + 1
        return True


@dataclass(frozen=True)
class StepResult:
    """What one step produced: the new sim time (s), a camera frame due for publication (with
    the sim time it was captured at, s: earlier with frame latency) and a lidar scan (ranges, m)
    if one was due, whether the robot/can state is due for publishing and, if so, the names of
    everything but the floor the robot touched at any step since the previous state (a brief
    touch between two states is not lost), and whether any touch since then was on the
    robot's front half (its bumper)."""

    time_s: float
    image: Optional[np.ndarray]
    state_due: bool
    touched: FrozenSet[str]
    scan: Optional[np.ndarray] = None
    image_time_s: Optional[float] = None
    clock_due: bool = True
    bumped: bool = False


@dataclass(frozen=True)
class Odometry2D:
    """The robot's odometry: pose in odom (x m, y m, yaw rad) and twist in base_link (linear
    m/s, angular rad/s)."""

    x_m: float
    y_m: float
    yaw_rad: float
    linear_mps: float
    angular_radps: float


def lidar_spec(config: SimpleNamespace) -> LidarSpec:
    """The lidar described by the parameters."""
    return LidarSpec(config.scan_beams, config.scan_range_min, config.scan_range_max,
                     config.scan_height, getattr(config, 'scan_field_deg', 360.0))


class Simulation:
    """Runs a World in sim time from (linear, angular) commands."""

    def __init__(self, world: World, physics_rate_hz: float, camera_rate_hz: float,
                 state_rate_hz: float, cmd_timeout_s: float, max_linear_accel_mps2: float,
                 max_angular_accel_radps2: float, encoding: str = 'bgr8',
                 lidar: Optional[LidarSpec] = None, scan_rate_hz: float = 0.0,
                 realism: Optional[Realism] = None, seed: int = 0, clock_rate_hz: float = 0.0):
        self.world = world
        self.physics_rate_hz = physics_rate_hz
        self.encoding = encoding
        self.lidar = lidar if scan_rate_hz > 0.0 else None
        self.steps = 0
        self._camera_schedule = RateSchedule(camera_rate_hz, physics_rate_hz)
        self._state_schedule = RateSchedule(state_rate_hz, physics_rate_hz)
        self._scan_schedule = (RateSchedule(scan_rate_hz, physics_rate_hz) if self.lidar
                               else None)
        self._clock_schedule = (RateSchedule(clock_rate_hz, physics_rate_hz)
                                if clock_rate_hz > 0.0 else None)
        self._watchdog = CommandWatchdog(cmd_timeout_s)
        self._limiter = TwistLimiter(max_linear_accel_mps2, max_angular_accel_radps2)
        self._touched = frozenset()
        self._bumped = False
        self.realism = realism if realism is not None else Realism(
            PRESETS['ideal'], world.camera.intrinsics, encoding, world.wheel_separation_m)
        self.seed = seed
        self.scan_wanted = True
        """Whether a due lidar scan is cast (the owner clears it while nobody reads the scans:
        360 ray casts cost more than the physics steps between two scans)."""
        self._new_trial()

    @classmethod
    def from_config(cls, world: World, config: SimpleNamespace) -> 'Simulation':
        """A Simulation of ``world`` with the rates, limits and realism of a
        :func:`checked_config`."""
        realism = Realism(spec_from_config(config), world.camera.intrinsics, config.encoding,
                          world.wheel_separation_m)
        return cls(world, config.physics_rate, config.camera_rate, config.state_rate,
                   config.cmd_timeout, config.max_linear_accel, config.max_angular_accel,
                   config.encoding, lidar_spec(config), config.scan_rate, realism, config.seed,
                   config.clock_rate)

    def _new_trial(self):
        """Reseed the realism models from the world's seed and the can's place (a trial is the
        same whatever ran before it) and start the odometry at the true pose."""
        self.realism.new_trial(trial_key(self.seed, self.world.can_home),
                               self.world.robot_pose())

    def odometry(self) -> Odometry2D:
        """The robot's odometry now: the true pose and twist when the odometry has no error."""
        if self.realism.spec.odometry_is_true:
            state = self.world.robot_state()
            return Odometry2D(state.position[0], state.position[1], state.yaw_rad,
                              state.linear_velocity[0], state.angular_velocity[2])
        odometry = self.realism.odometry
        return Odometry2D(*odometry.pose, *odometry.twist)

    @property
    def time_s(self) -> float:
        """Sim time (s) of the current state."""
        return self.steps / self.physics_rate_hz

    @property
    def executed_twist(self) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) the wheels are driven at, after the limits."""
        return self._limiter.linear_mps, self._limiter.angular_radps

    def command(self, linear_mps: float, angular_radps: float):
        """A new velocity command, received now in sim time (it acts after the command
        latency)."""
        self.realism.actuation.command(linear_mps, angular_radps, self.time_s)

    def reset_robot(self):
        """Robot back to the start pose at rest; the pending command is dropped. Frames, scans
        and states are counted from here, so a trial sees them at the same times after its
        reset wherever between two frames the reset came."""
        self._watchdog.reset()
        self._limiter.reset()
        self.world.reset_robot()
        self._touched = frozenset()
        self._bumped = False
        for schedule in self._schedules():
            schedule.restart(self.steps)

    def _schedules(self):
        return [schedule for schedule in (self._camera_schedule, self._state_schedule,
                                          self._scan_schedule, self._clock_schedule)
                if schedule is not None]

    def reset(self):
        """Robot back to the start pose at rest, can upright at its last placement; the
        realism models start the trial anew."""
        self.reset_robot()
        self.world.place_can(*self.world.can_home)
        self._new_trial()

    def reset_trial(self, can_xy: Optional[Tuple[float, float]]) -> Tuple[bool, str]:
        """Robot at the start pose at rest, can upright at ``can_xy`` (odom, m) or, when None,
        at its last placement; (success, why). A refused placement leaves the can at its last
        placement."""
        self.reset_robot()
        self.world.place_can(*self.world.can_home)
        if can_xy is None:
            placed = True, 'robot at the start, can at (%.3f, %.3f)' % self.world.can_home
        else:
            placed = self.place_can(*can_xy)
        self._new_trial()
        return placed

    def set_scene(self, scene: Scene, seed: Optional[int] = None):
        """A new world (walls, obstacles, can), drawn from ``seed`` (the realism models' seed
        too, when given); the robot back to the start pose at rest."""
        self.reset_robot()
        self.world.set_scene(scene)
        if seed is not None:
            self.seed = seed
        self._new_trial()

    def place_can(self, x_m: float, y_m: float) -> Tuple[bool, str]:
        """Stand the can at (x, y) in odom (m) unless that is off the floor or overlaps a wall,
        an obstacle or the robot; (success, why)."""
        problem = self.world.scene.can_place_problem(x_m, y_m)
        if problem is not None:
            return False, problem
        robot_x_m, robot_y_m, _ = self.world.robot_state().position
        gap_m = (math.hypot(x_m - robot_x_m, y_m - robot_y_m)
                 - (self.world.body_radius_m + CAN_RADIUS_M))
        if gap_m < 0.0:
            return False, ('can at (%.3f, %.3f) would overlap the robot at (%.3f, %.3f)'
                           % (x_m, y_m, robot_x_m, robot_y_m))
        self.world.place_can(x_m, y_m)
        return True, 'can placed at (%.3f, %.3f)' % (x_m, y_m)

    def step(self) -> StepResult:
        """Advance one physics step; render and scan when due."""
        realism = self.realism
        for acts_s, linear_mps, angular_radps in realism.actuation.arrived(self.time_s):
            self._watchdog.command(linear_mps, angular_radps, acts_s)
        dt_s = 1.0 / self.physics_rate_hz
        before = self._limiter.linear_mps, self._limiter.angular_radps
        linear_mps, angular_radps = self._limiter.step(*self._watchdog.target(self.time_s), dt_s)
        self.world.set_twist(*realism.actuation.wheels(linear_mps, angular_radps))
        self.world.step()
        self.steps += 1
        if not realism.spec.odometry_is_true:
            half_track = self.world.wheel_separation_m / 2.0
            linear_accel = (linear_mps - before[0]) / dt_s
            turn_accel = (angular_radps - before[1]) * half_track / dt_s
            realism.odometry.update(self.world.robot_pose(), dt_s,
                                    (linear_accel - turn_accel, linear_accel + turn_accel))
        touched, front = self.world.touches()
        self._touched = self._touched | touched
        self._bumped = self._bumped or front
        if self._camera_schedule.due(self.steps):
            self._capture()
        delivered = realism.frames.due(self.time_s)
        image_time_s, image = delivered[-1] if delivered else (None, None)
        scan_due = self._scan_schedule is not None and self._scan_schedule.due(self.steps)
        scan = (realism.scan(self.world.scan(self.lidar)) if scan_due and self.scan_wanted
                else None)
        state_due = self._state_schedule.due(self.steps)
        clock_due = (self._clock_schedule is None or self._clock_schedule.due(self.steps)
                     or state_due or image is not None or scan is not None)
        if not state_due:
            return StepResult(self.time_s, image, False, frozenset(), scan, image_time_s,
                              clock_due)
        touched, self._touched = self._touched, frozenset()
        bumped, self._bumped = self._bumped, False
        return StepResult(self.time_s, image, True, touched, scan, image_time_s, clock_due,
                          bumped)

    def _capture(self):
        """Render a frame as the camera sees it now and hand it to the frame delivery."""
        camera = self.realism.camera
        image = self.world.render(self.encoding, camera.light_direction, camera.render_margin_px)
        if not camera.identity:
            state = self.world.robot_state()
            image = camera.apply(image, state.linear_velocity[0], state.angular_velocity[2])
        self.realism.frames.capture(self.time_s, image)
