"""The simulator's parameters and its sim-time loop: commands in, physics steps, frames out.

Time is counted in physics steps (exact sim time, no float drift). Each step applies the
acceleration-limited twist of the freshest command (zero once it is older than the timeout),
steps pybullet once, and says whether a camera frame and a state message are due.
"""
import math
import random
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Callable, Optional, Tuple

import numpy as np

from can_seeker.camera_mount import CameraMount
from can_seeker.sim.drive import CommandWatchdog, TwistLimiter
from can_seeker.params import Param
from can_seeker.sim.world import (BODY_RADIUS_M, CAN_RADIUS_M, CAN_RGBA, RENDERERS, CameraSpec,
                              World)

DEFAULT_CAN_RGBA = ' '.join('%g' % channel for channel in CAN_RGBA)

PARAMS = (
    Param('gui', False, 'open the pybullet GUI; only when a display exists (DISPLAY set), '
          'headless otherwise'),
    Param('renderer', 'auto', 'camera renderer: auto (EGL, TinyRenderer if EGL fails), egl or '
          'tiny', choices=RENDERERS),
    Param('width', 320, 'image width (px)', 16, 4096),
    Param('height', 240, 'image height (px)', 16, 4096),
    Param('fov_deg', 45.0, 'vertical field of view (deg)', 10.0, 120.0),
    Param('encoding', 'bgr8', 'image encoding of /camera/image_raw', choices=('bgr8', 'rgb8')),
    Param('camera_rate', 15.0, 'camera frame rate (Hz, sim time)', 0.1, 240.0),
    Param('camera_height', 0.25, 'height of camera_link above the floor (m)', 0.1, 1.5),
    Param('camera_pitch_deg', 25.0, 'camera pitch below the horizon (deg, positive down)',
          -30.0, 80.0),
    Param('physics_rate', 240.0, 'physics steps per second of sim time (Hz); /clock ticks at '
          'every step', 60.0, 2000.0),
    Param('state_rate', 50.0, 'rate of /odom, TF odom->base_link, /sim/can_pose and /sim/contact '
          '(Hz, sim time)', 1.0, 1000.0),
    Param('real_time_factor', 1.0, 'sim seconds per wall-clock second; 0 runs as fast as '
          'possible', 0.0, 1000.0),
    Param('cmd_timeout', 0.5, 'brake to a stop when the last /cmd_vel is older than this '
          '(s, sim time)', 0.01, 60.0),
    Param('max_linear_accel', 1.0, 'linear acceleration limit of the base (m/s^2)', 0.01, 20.0),
    Param('max_angular_accel', 4.0, 'angular acceleration limit of the base (rad/s^2)',
          0.01, 100.0),
    Param('can_placement', 'random', 'random: can centre at a random bearing and a distance '
          'drawn from ~seed in [~can_min_distance, ~can_max_distance] from the robot start; '
          'fixed: at (~can_x, ~can_y)', choices=('random', 'fixed')),
    Param('can_x', 1.0, 'can centre x in odom when ~can_placement is fixed (m)', -100.0, 100.0),
    Param('can_y', 0.0, 'can centre y in odom when ~can_placement is fixed (m)', -100.0, 100.0),
    Param('seed', 0, 'random seed of the can placement', 0, 2 ** 31 - 1),
    Param('can_min_distance', 0.5, 'nearest random can centre from the robot start (m)',
          0.3, 50.0),
    Param('can_max_distance', 3.0, 'farthest random can centre from the robot start (m)',
          0.3, 50.0),
    Param('can_rgba', DEFAULT_CAN_RGBA, 'can colour: red green blue alpha, four numbers in 0-1'),
    Param('lockstep', False, 'after each camera frame, step no further until every '
          '~lockstep_topics topic and the stamped command (cmd_vel_stamped) answered it with a '
          'message stamped at or after the frame (or ~lockstep_timeout passed); the base then '
          'follows cmd_vel_stamped only'),
    Param('lockstep_topics', '/image_converter/detection', 'topics with a std_msgs/Header '
          'whose stamp must reach the frame stamp before the next step in lockstep, separated '
          'by spaces; a topic without a publisher is not waited for'),
    Param('lockstep_timeout', 2.0, 'wall-clock seconds a frame waits for its answers in '
          'lockstep before the simulation steps on (counted, with a warning)', 0.01, 600.0),
)

MIN_CAN_CLEARANCE_M = BODY_RADIUS_M + CAN_RADIUS_M
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


def random_can_position(seed: int, min_distance_m: float,
                        max_distance_m: float) -> Tuple[float, float]:
    """Can centre (x, y) (m) at a uniformly random bearing and distance from the origin."""
    generator = random.Random(seed)
    distance_m = generator.uniform(min_distance_m, max_distance_m)
    bearing_rad = generator.uniform(-math.pi, math.pi)
    return distance_m * math.cos(bearing_rad), distance_m * math.sin(bearing_rad)


def checked_config(params: SimpleNamespace, warn: Callable[[str], None]) -> SimpleNamespace:
    """``params`` with the checks that span parameters applied: bad values warned and replaced.

    Adds ``can_color`` (the parsed ~can_rgba) and ``can_position`` (where the can starts).
    """
    config = SimpleNamespace(**vars(params))
    try:
        config.can_color = parse_rgba(config.can_rgba)
    except ValueError as error:
        warn('parameter ~can_rgba: %s; using the default %r' % (error, DEFAULT_CAN_RGBA))
        config.can_rgba = DEFAULT_CAN_RGBA
        config.can_color = parse_rgba(DEFAULT_CAN_RGBA)
    for name in ('camera_rate', 'state_rate'):
        if getattr(config, name) > config.physics_rate:
            warn('~%s %r is above ~physics_rate %r; using %r'
                 % (name, getattr(config, name), config.physics_rate, config.physics_rate))
            setattr(config, name, config.physics_rate)
    if config.can_max_distance < config.can_min_distance:
        warn('~can_max_distance %r is below ~can_min_distance %r; using %r for both'
             % (config.can_max_distance, config.can_min_distance, config.can_min_distance))
        config.can_max_distance = config.can_min_distance
    if config.can_placement == 'fixed':
        config.can_position = (config.can_x, config.can_y)
        if math.hypot(*config.can_position) < MIN_CAN_CLEARANCE_M:
            defaults = {spec.name: spec.default for spec in PARAMS}
            fallback = (defaults['can_x'], defaults['can_y'])
            warn('(~can_x, ~can_y) = %r overlaps the robot; placing the can at %r'
                 % (config.can_position, fallback))
            config.can_position = fallback
    else:
        config.can_position = random_can_position(config.seed, config.can_min_distance,
                                                  config.can_max_distance)
    return config


def camera_spec(config: SimpleNamespace) -> CameraSpec:
    """The camera described by the parameters."""
    return CameraSpec(config.width, config.height, config.fov_deg,
                      CameraMount(config.camera_height, config.camera_pitch_deg))


class RateSchedule:
    """Says at which physics steps an event of ``rate_hz`` is due: the first one period after
    step 0, then at the first step at or after each multiple of the period (no drift)."""

    def __init__(self, rate_hz: float, physics_rate_hz: float):
        self._steps_per_event = physics_rate_hz / rate_hz
        self._next_event = 1

    def due(self, step: int) -> bool:
        """Whether the event is due at ``step``; call once per step, in order."""
        if step + 1e-9 < self._next_event * self._steps_per_event:
            return False
        self._next_event = math.floor(step / self._steps_per_event + 1e-9) + 1
        return True


@dataclass(frozen=True)
class StepResult:
    """What one step produced: the new sim time (s), a camera frame if one was due, whether the
    robot/can state is due for publishing and, if so, whether the robot touched the can at any
    step since the previous state (a brief touch between two states is not lost)."""

    time_s: float
    image: Optional[np.ndarray]
    state_due: bool
    touched_can: bool


class Simulation:
    """Runs a World in sim time from (linear, angular) commands."""

    def __init__(self, world: World, physics_rate_hz: float, camera_rate_hz: float,
                 state_rate_hz: float, cmd_timeout_s: float, max_linear_accel_mps2: float,
                 max_angular_accel_radps2: float, encoding: str = 'bgr8'):
        self.world = world
        self.physics_rate_hz = physics_rate_hz
        self.encoding = encoding
        self.steps = 0
        self._camera_schedule = RateSchedule(camera_rate_hz, physics_rate_hz)
        self._state_schedule = RateSchedule(state_rate_hz, physics_rate_hz)
        self._watchdog = CommandWatchdog(cmd_timeout_s)
        self._limiter = TwistLimiter(max_linear_accel_mps2, max_angular_accel_radps2)
        self._touched_can = False

    @classmethod
    def from_config(cls, world: World, config: SimpleNamespace) -> 'Simulation':
        """A Simulation of ``world`` with the rates and limits of a :func:`checked_config`."""
        return cls(world, config.physics_rate, config.camera_rate, config.state_rate,
                   config.cmd_timeout, config.max_linear_accel, config.max_angular_accel,
                   config.encoding)

    @property
    def time_s(self) -> float:
        """Sim time (s) of the current state."""
        return self.steps / self.physics_rate_hz

    @property
    def executed_twist(self) -> Tuple[float, float]:
        """The (linear m/s, angular rad/s) the wheels are driven at, after the limits."""
        return self._limiter.linear_mps, self._limiter.angular_radps

    def command(self, linear_mps: float, angular_radps: float):
        """A new velocity command, received now in sim time."""
        self._watchdog.command(linear_mps, angular_radps, self.time_s)

    def reset_robot(self):
        """Robot back to the start pose at rest; the pending command is dropped."""
        self._watchdog.reset()
        self._limiter.reset()
        self.world.reset_robot()
        self._touched_can = False

    def reset(self):
        """Robot back to the start pose at rest, can upright at its last placement."""
        self.reset_robot()
        self.world.place_can(*self.world.can_home)

    def reset_trial(self, can_xy: Optional[Tuple[float, float]]) -> Tuple[bool, str]:
        """Robot at the start pose at rest, can upright at ``can_xy`` (odom, m) or, when None,
        at its last placement; (success, why). A refused placement leaves the can at its last
        placement."""
        self.reset()
        if can_xy is None:
            return True, 'robot at the start, can at (%.3f, %.3f)' % self.world.can_home
        return self.place_can(*can_xy)

    def place_can(self, x_m: float, y_m: float) -> Tuple[bool, str]:
        """Stand the can at (x, y) in odom (m) unless that overlaps the robot; (success, why)."""
        if not (math.isfinite(x_m) and math.isfinite(y_m)):
            return False, 'can position (%r, %r) is not finite' % (x_m, y_m)
        robot_x_m, robot_y_m, _ = self.world.robot_state().position
        gap_m = math.hypot(x_m - robot_x_m, y_m - robot_y_m) - MIN_CAN_CLEARANCE_M
        if gap_m < 0.0:
            return False, ('can at (%.3f, %.3f) would overlap the robot at (%.3f, %.3f)'
                           % (x_m, y_m, robot_x_m, robot_y_m))
        self.world.place_can(x_m, y_m)
        return True, 'can placed at (%.3f, %.3f)' % (x_m, y_m)

    def step(self) -> StepResult:
        """Advance one physics step; render when a camera frame is due."""
        linear_mps, angular_radps = self._limiter.step(*self._watchdog.target(self.time_s),
                                                       1.0 / self.physics_rate_hz)
        self.world.set_twist(linear_mps, angular_radps)
        self.world.step()
        self.steps += 1
        self._touched_can = self._touched_can or self.world.robot_touches_can()
        image = (self.world.render(self.encoding) if self._camera_schedule.due(self.steps)
                 else None)
        if not self._state_schedule.due(self.steps):
            return StepResult(self.time_s, image, False, False)
        touched_can, self._touched_can = self._touched_can, False
        return StepResult(self.time_s, image, True, touched_can)
