"""The URDF (robot_description) agrees with the simulator's constants and default camera mount."""
import math
import pathlib
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from can_seeker.camera_geometry import quaternion_matrix
from can_seeker.camera_mount import OPTICAL_IN_CAMERA_LINK_XYZW, CameraMount
from can_seeker.sim.simulation import PARAMS
from can_seeker.sim.scene import ROBOT_RADIUS_M as BODY_RADIUS_M, WHEEL_RADIUS_M, WHEEL_SEPARATION_M
from urdf_checks import joint_origin, rpy_matrix

URDF = pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf'
DEFAULTS = {spec.name: spec.default for spec in PARAMS}


@pytest.fixture(scope='module')
def robot():
    return ET.parse(URDF).getroot()




def test_camera_joint_is_the_default_mount(robot):
    mount = CameraMount(DEFAULTS['camera_height'], DEFAULTS['camera_pitch_deg'])
    xyz, rpy = joint_origin(robot, 'camera_joint')
    assert xyz == pytest.approx(list(mount.translation_m))
    assert np.allclose(rpy_matrix(*rpy), quaternion_matrix(*mount.rotation_xyzw), atol=1e-6)


def test_optical_joint_is_the_rep103_optical_rotation(robot):
    xyz, rpy = joint_origin(robot, 'camera_optical_joint')
    assert xyz == [0.0, 0.0, 0.0]
    assert np.allclose(rpy_matrix(*rpy), quaternion_matrix(*OPTICAL_IN_CAMERA_LINK_XYZW),
                       atol=1e-6)


def test_optical_axis_looks_forward_and_down():
    mount = CameraMount(0.25, 25.0)
    optical_in_base = (quaternion_matrix(*mount.rotation_xyzw)
                       @ quaternion_matrix(*OPTICAL_IN_CAMERA_LINK_XYZW))
    pitch_rad = math.radians(25.0)
    assert optical_in_base[:, 2] == pytest.approx((math.cos(pitch_rad), 0.0, -math.sin(pitch_rad)))
    assert optical_in_base[:, 0] == pytest.approx((0.0, -1.0, 0.0))


def test_wheels_match_the_drive_constants(robot):
    left, _ = joint_origin(robot, 'left_wheel_joint')
    right, _ = joint_origin(robot, 'right_wheel_joint')
    assert left[1] - right[1] == pytest.approx(WHEEL_SEPARATION_M)
    assert left[2] == right[2] == pytest.approx(WHEEL_RADIUS_M)
    for wheel in ('left_wheel', 'right_wheel'):
        sphere = robot.find("link[@name='%s']/collision/geometry/sphere" % wheel)
        assert float(sphere.get('radius')) == pytest.approx(WHEEL_RADIUS_M)


def test_body_radius_matches(robot):
    body = robot.find("link[@name='base_link']/collision/geometry/cylinder")
    assert float(body.get('radius')) == pytest.approx(BODY_RADIUS_M)
