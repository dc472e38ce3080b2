"""Robot profiles: the body, wheels, speed limits, camera, lidar and bumper of one robot, read
from a YAML file in ``config/robots/`` (or any path), and what they mean for each node.

A profile file has a ``robot_profile`` section (the figures, units in their names) and a
section per node whose parameters the figures set (``obstacle_scan``, ``can_stopper``) in the
nodes' own parameter names: robot.launch loads the file as it is with ``<rosparam>``, so the
node sections are what the nodes get. The camera mount is no node parameter: the nodes take it
from TF, which robot_description (``--robot``) and robot_state.launch make from the figures.
The node sections take the figures by YAML alias (``*body_radius_m``), so each figure is
written once; :func:`load_profile` checks that every node parameter
:func:`node_params` derives from the figures is in the file with that value (a clear error
otherwise), and lets the node sections hold further node parameters (tuning for this robot).
The simulator and robot_description build the robot from the same figures. No rospy here.
"""
import math
import os
from dataclasses import dataclass
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

import yaml

from can_seeker.camera_mount import CameraMount
from can_seeker.sim.lidar import LidarSpec

PROFILE_SECTION = 'robot_profile'
NODES = ('image_converter', 'obstacle_scan', 'can_stopper')
TOPIC_KEYS = ('camera', 'image', 'image_transport', 'cmd_vel', 'odom', 'base_frame', 'scan',
              'bumper')
"""robot.launch arguments a profile's ``topics`` names for its driver (roslaunch takes
remappings from arguments only, so these are printed by ``robot_params``, not loaded)."""


class ProfileError(ValueError):
    """A profile file that cannot be read or whose figures are missing, wrong or disagree."""


@dataclass(frozen=True)
class CameraProfile:
    """Where the camera sits (camera_link in base_link: forward and height above the floor,
    pitch below the horizon) and its vertical field of view."""

    height_m: float
    pitch_deg: float
    forward_m: float
    vertical_fov_deg: float


@dataclass(frozen=True)
class LidarProfile:
    """A planar lidar: range limits, scan rate, field of view about straight ahead, beam count
    and the beams' height above the floor. A profile without one says ``lidar: false`` (a
    parameter server holds no null)."""

    range_min_m: float
    range_max_m: float
    rate_hz: float
    field_deg: float
    beams: int
    height_m: float


@dataclass(frozen=True)
class RobotProfile:
    """One robot. ``body_radius_m`` is the disc about base_link the nodes keep clear (their
    ``robot_radius``); the body is that disc, or, when ``footprint_m`` (x_min, x_max, y_min,
    y_max in base_link) is given, that rectangle, which the disc must hold. Speed and
    acceleration limits are those the nodes keep to on this robot."""

    name: str
    body_height_m: float
    wheel_separation_m: float
    wheel_radius_m: float
    mass_kg: float
    max_linear_mps: float
    max_angular_radps: float
    max_linear_accel_mps2: float
    max_angular_accel_radps2: float
    camera: CameraProfile
    lidar: Optional[LidarProfile]
    bumper: bool
    body_radius_m: float = 0.0
    footprint_m: Optional[Tuple[float, float, float, float]] = None
    topics: Tuple[Tuple[str, str], ...] = ()

    @property
    def footprint_radius_m(self) -> float:
        """Distance from base_link to the body's farthest point (m)."""
        if self.footprint_m is None:
            return self.body_radius_m
        x_min, x_max, y_min, y_max = self.footprint_m
        return max(math.hypot(x, y) for x in (x_min, x_max) for y in (y_min, y_max))


def camera_mount(profile: RobotProfile) -> CameraMount:
    """The profile's camera mount."""
    camera = profile.camera
    return CameraMount(camera.height_m, camera.pitch_deg, camera.forward_m)


def lidar_spec(profile: RobotProfile) -> Optional[LidarSpec]:
    """The profile's lidar for the simulator (None: it has none)."""
    lidar = profile.lidar
    if lidar is None:
        return None
    return LidarSpec(lidar.beams, lidar.range_min_m, lidar.range_max_m, lidar.height_m,
                     lidar.field_deg)


def _number(section: Mapping, key: str, where: str, minimum: float, maximum: float) -> float:
    if key not in section:
        raise ProfileError('%s: %s is missing' % (where, key))
    value = section[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise ProfileError('%s: %s must be a number, got %r' % (where, key, value))
    if not minimum <= value <= maximum:
        raise ProfileError('%s: %s = %r is outside %g .. %g' % (where, key, value, minimum,
                                                                maximum))
    return float(value)


def _section(data: Mapping, key: str, where: str) -> Mapping:
    value = data.get(key)
    if not isinstance(value, dict):
        raise ProfileError('%s: %s must be a mapping, got %r' % (where, key, value))
    return value


def _camera(section: Mapping, where: str) -> CameraProfile:
    where += '.camera'
    return CameraProfile(_number(section, 'height_m', where, 0.02, 2.0),
                         _number(section, 'pitch_deg', where, -30.0, 80.0),
                         _number(section, 'forward_m', where, -1.0, 1.0),
                         _number(section, 'vertical_fov_deg', where, 10.0, 120.0))


def _lidar(section: Mapping, where: str) -> LidarProfile:
    where += '.lidar'
    beams = _number(section, 'beams', where, 1, 100000)
    if beams != int(beams):
        raise ProfileError('%s: beams must be a whole number, got %r' % (where, beams))
    lidar = LidarProfile(_number(section, 'range_min_m', where, 0.0, 100.0),
                         _number(section, 'range_max_m', where, 0.01, 100.0),
                         _number(section, 'rate_hz', where, 0.1, 100.0),
                         _number(section, 'field_deg', where, 1.0, 360.0), int(beams),
                         _number(section, 'height_m', where, 0.0, 2.0))
    if lidar.range_max_m <= lidar.range_min_m:
        raise ProfileError('%s: range_max_m %r is not above range_min_m %r'
                           % (where, lidar.range_max_m, lidar.range_min_m))
    return lidar


def _footprint(value, where: str) -> Tuple[float, float, float, float]:
    if not isinstance(value, dict):
        raise ProfileError('%s: footprint_m must be a mapping of x_min, x_max, y_min, y_max'
                           % where)
    where += '.footprint_m'
    x_min, x_max, y_min, y_max = (_number(value, key, where, -2.0, 2.0)
                                  for key in ('x_min', 'x_max', 'y_min', 'y_max'))
    if not (x_min < 0.0 < x_max and y_min < 0.0 < y_max):
        raise ProfileError('%s: the rectangle must hold base_link (x_min < 0 < x_max, '
                           'y_min < 0 < y_max)' % where)
    return x_min, x_max, y_min, y_max


def profile_from_dict(data: Any, name: str) -> RobotProfile:
    """The profile in the mapping a profile file holds; ProfileError saying what is wrong."""
    if not isinstance(data, dict):
        raise ProfileError('%s: a profile is a mapping, got %r' % (name, data))
    where = '%s: %s' % (name, PROFILE_SECTION)
    section = _section(data, PROFILE_SECTION, name)
    lidar = section.get('lidar')
    bumper = section.get('bumper')
    if not isinstance(bumper, bool):
        raise ProfileError('%s: bumper must be true or false, got %r' % (where, bumper))
    topics = section.get('topics') or {}
    if not isinstance(topics, dict) or set(topics) - set(TOPIC_KEYS):
        raise ProfileError('%s: topics may name only %s' % (where, ', '.join(TOPIC_KEYS)))
    profile = RobotProfile(
        name=name,
        body_height_m=_number(section, 'body_height_m', where, 0.01, 2.0),
        wheel_separation_m=_number(section, 'wheel_separation_m', where, 0.02, 2.0),
        wheel_radius_m=_number(section, 'wheel_radius_m', where, 0.005, 0.5),
        mass_kg=_number(section, 'mass_kg', where, 0.1, 500.0),
        max_linear_mps=_number(section, 'max_linear_mps', where, 0.01, 2.0),
        max_angular_radps=_number(section, 'max_angular_radps', where, 0.05, 6.0),
        max_linear_accel_mps2=_number(section, 'max_linear_accel_mps2', where, 0.05, 5.0),
        max_angular_accel_radps2=_number(section, 'max_angular_accel_radps2', where, 0.1, 20.0),
        camera=_camera(_section(section, 'camera', where), where),
        lidar=None if lidar in (None, False) else _lidar(_section(section, 'lidar', where), where),
        bumper=bumper,
        body_radius_m=_number(section, 'body_radius_m', where, 0.02, 2.0),
        footprint_m=(_footprint(section['footprint_m'], where) if 'footprint_m' in section
                     else None),
        topics=tuple(sorted((key, str(value)) for key, value in topics.items())))
    if profile.footprint_radius_m > profile.body_radius_m + 1e-9:
        raise ProfileError('%s: body_radius_m %r does not hold the footprint (its far corner is '
                           '%.4f m from base_link)' % (where, profile.body_radius_m,
                                                       profile.footprint_radius_m))
    if profile.wheel_separation_m / 2.0 > profile.body_radius_m:
        raise ProfileError('%s: the wheels (wheel_separation_m %r) stick out of the body'
                           % (where, profile.wheel_separation_m))
    return profile


def node_params(profile: RobotProfile) -> Dict[str, Dict[str, Any]]:
    """The node parameters the profile's figures set, by node name."""
    return {
        'obstacle_scan': {'robot_radius': profile.body_radius_m,
                          'robot_height': profile.body_height_m},
        'can_stopper': {'robot_radius': profile.body_radius_m,
                        'max_linear': profile.max_linear_mps,
                        'max_angular': profile.max_angular_radps,
                        'max_linear_accel': profile.max_linear_accel_mps2,
                        'max_angular_accel': profile.max_angular_accel_radps2},
    }


def _close(a, b) -> bool:
    return isinstance(a, (int, float)) and not isinstance(a, bool) and math.isclose(
        a, b, rel_tol=1e-9, abs_tol=1e-9)


def _null_keys(data, prefix=''):
    if isinstance(data, dict):
        return [key for name, value in data.items()
                for key in _null_keys(value, '%s%s/' % (prefix, name))]
    return [prefix.rstrip('/')] if data is None else []


def check_node_sections(data: Mapping, profile: RobotProfile):
    """ProfileError unless each node section holds every parameter :func:`node_params` derives,
    with that value (other keys are the nodes' own business)."""
    problems = []
    for node, expected in node_params(profile).items():
        section = data.get(node)
        if not isinstance(section, dict):
            problems.append('%s: section missing' % node)
            continue
        for key, value in expected.items():
            if key not in section:
                problems.append('%s/%s missing (should be %.6g)' % (node, key, value))
            elif not _close(section[key], value):
                problems.append('%s/%s is %r, the figures give %.6g' % (node, key, section[key],
                                                                       value))
    if problems:
        raise ProfileError('%s: the node sections disagree with %s: %s'
                           % (profile.name, PROFILE_SECTION, '; '.join(problems)))


def profile_path(robot: str, search_dirs: Sequence[str]) -> str:
    """The file ``robot`` names: an existing path, or NAME.yaml in one of ``search_dirs``."""
    if os.path.isfile(robot):
        return robot
    for folder in search_dirs:
        candidate = os.path.join(folder, robot if robot.endswith('.yaml') else robot + '.yaml')
        if os.path.isfile(candidate):
            return candidate
    raise ProfileError('no robot profile %r (looked in %s)'
                       % (robot, ', '.join(search_dirs) or 'the current directory'))


def load_profile(robot: str, search_dirs: Sequence[str] = ()) -> RobotProfile:
    """The checked profile ``robot`` names (a path or a name in ``search_dirs``)."""
    path = profile_path(robot, search_dirs)
    name = os.path.splitext(os.path.basename(path))[0]
    try:
        with open(path) as stream:
            data = yaml.safe_load(stream)
    except (OSError, yaml.YAMLError) as error:
        raise ProfileError('cannot read robot profile %s: %s' % (path, error))
    nulls = _null_keys(data)
    if nulls:
        raise ProfileError('%s: %s empty: robot.launch loads the file onto the parameter '
                           'server, which holds no null (say false or "")' % (name, ', '.join(nulls)))
    profile = profile_from_dict(data, name)
    check_node_sections(data, profile)
    return profile


def launch_arguments(profile: RobotProfile, robot: Optional[str] = None) -> str:
    """The robot.launch command line for this robot's driver topics; ``robot`` is its
    ``robot:=`` value (a profile read from a file outside config/robots/ is named by its
    absolute path, the only way robot.launch finds it); default the profile's name."""
    return ' '.join(['roslaunch can_seeker robot.launch robot:=%s' % (robot or profile.name)]
                    + ['%s:=%s' % (key, value or '""') for key, value in profile.topics])
