"""Where the camera sits on the robot: base_link -> camera_link -> camera_optical_frame.

camera_link is REP-103 (x forward, z up) pitched down by the mount pitch; camera_optical_frame
is its optical frame (z forward, x right, y down). The URDF holds the default mount;
:mod:`can_seeker.robot_model` applies another one.
"""
import math
import random
from dataclasses import dataclass
from typing import Any, Callable, Tuple

from can_seeker.params import Param, read_params

CAMERA_FORWARD_M = 0.12
"""Distance of camera_link ahead of base_link (m)."""

OPTICAL_IN_CAMERA_LINK_XYZW = (-0.5, 0.5, -0.5, 0.5)
"""Rotation of camera_optical_frame in camera_link (quaternion x, y, z, w), i.e. URDF rpy
(-pi/2, 0, -pi/2)."""


@dataclass(frozen=True)
class CameraMount:
    """The camera's height above the floor (m), pitch below the horizon (deg, positive down)
    and distance ahead of base_link (m)."""

    height_m: float
    pitch_deg: float
    forward_m: float = CAMERA_FORWARD_M

    @property
    def translation_m(self) -> Tuple[float, float, float]:
        """camera_link origin in base_link (m); base_link lies on the floor."""
        return (self.forward_m, 0.0, self.height_m)

    @property
    def rotation_xyzw(self) -> Tuple[float, float, float, float]:
        """camera_link orientation in base_link: a positive rotation about y tilts x downward."""
        half_rad = math.radians(self.pitch_deg) / 2.0
        return (0.0, math.sin(half_rad), 0.0, math.cos(half_rad))


RANDOM_HEIGHT_RANGE_M = (0.15, 0.35)
"""Heights a random mount is drawn from (m): a small base's deck to a mast."""
RANDOM_PITCH_RANGE_DEG = (15.0, 35.0)
"""Pitches a random mount is drawn from (deg below the horizon)."""


def random_mount(seed: int) -> CameraMount:
    """A camera mount drawn uniformly from RANDOM_HEIGHT_RANGE_M and RANDOM_PITCH_RANGE_DEG by
    ``seed``, from a random stream of its own (a world's geometry and looks are the same
    whether its mount is drawn or not)."""
    generator = random.Random('camera mount %d' % seed)
    return CameraMount(round(generator.uniform(*RANDOM_HEIGHT_RANGE_M), 4),
                       round(generator.uniform(*RANDOM_PITCH_RANGE_DEG), 3))


MOUNT_PARAMS = (
    Param('camera_height', 0.25, 'height of camera_link above the floor (m)', 0.1, 1.5),
    Param('camera_pitch_deg', 25.0, 'camera pitch below the horizon (deg, positive down)',
          -30.0, 80.0),
)
"""The simulator's mount parameters; robot_description reads them the same way."""


def mount_from_params(get_param: Callable[[str, Any], Any],
                      warn: Callable[[str], None]) -> CameraMount:
    """The mount from ``~camera_height`` and ``~camera_pitch_deg`` as the simulator reads them:
    an invalid value is reported through ``warn`` and replaced by its default."""
    config = read_params(MOUNT_PARAMS, get_param, warn)
    return CameraMount(config.camera_height, config.camera_pitch_deg)
