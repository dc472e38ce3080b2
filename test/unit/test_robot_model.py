"""The robot model for any camera mount: the URDF of robot_description and of the simulator."""
import io
import math
import pathlib
import random
import xml.etree.ElementTree as ET
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pytest

from can_seeker.camera_geometry import quaternion_matrix
from can_seeker.camera_mount import (MOUNT_PARAMS, OPTICAL_IN_CAMERA_LINK_XYZW, CameraMount,
                                     mount_from_params)
from can_seeker.robot_model import MAST_GAP_M, robot_urdf, rpy_from_quaternion
from can_seeker.sim.world import CameraSpec, World
from can_seeker.tools import robot_description
from urdf_checks import joint_origin, rpy_matrix

URDF = pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf'
TEMPLATE = URDF.read_text()
MOUNTS = [CameraMount(0.15, 15.0), CameraMount(0.35, 35.0), CameraMount(0.1, -30.0),
          CameraMount(1.5, 80.0)]




def mast(robot):
    """(bottom, top) height of the camera mast (m), or None without one."""
    visual = robot.find("link[@name='base_link']/visual[@name='camera_mast']")
    if visual is None:
        return None
    z = float(visual.find('origin').get('xyz').split()[2])
    length = float(visual.find('geometry/cylinder').get('length'))
    return z - length / 2.0, z + length / 2.0


def test_rpy_from_quaternion_is_the_urdf_convention():
    rng = random.Random(7)
    for _ in range(200):
        quaternion = np.array([rng.gauss(0.0, 1.0) for _ in range(4)])
        quaternion /= np.linalg.norm(quaternion)
        assert np.allclose(rpy_matrix(*rpy_from_quaternion(*quaternion)),
                           quaternion_matrix(*quaternion), atol=1e-9)


def test_default_mount_keeps_the_file_as_it_is():
    template, mounted = ET.fromstring(TEMPLATE), ET.fromstring(robot_urdf(TEMPLATE,
                                                                          CameraMount(0.25, 25.0)))
    for joint in ('camera_joint', 'camera_optical_joint'):
        (xyz, rpy), (xyz_0, rpy_0) = joint_origin(mounted, joint), joint_origin(template, joint)
        assert xyz == pytest.approx(xyz_0, abs=1e-9)
        assert rpy == pytest.approx(rpy_0, abs=1e-6)
    assert mast(mounted) == pytest.approx(mast(template))
    assert [element.tag for element in mounted.iter()] == [element.tag for element in template.iter()]


@pytest.mark.parametrize('mount', MOUNTS, ids=lambda m: '%gm_%gdeg' % (m.height_m, m.pitch_deg))
def test_camera_joints_are_the_mount(mount):
    robot = ET.fromstring(robot_urdf(TEMPLATE, mount))
    xyz, rpy = joint_origin(robot, 'camera_joint')
    assert xyz == pytest.approx(list(mount.translation_m), abs=1e-12)
    assert np.allclose(rpy_matrix(*rpy), quaternion_matrix(*mount.rotation_xyzw), atol=1e-12)
    assert rpy == pytest.approx([0.0, math.radians(mount.pitch_deg), 0.0], abs=1e-12)
    xyz, rpy = joint_origin(robot, 'camera_optical_joint')
    assert xyz == [0.0, 0.0, 0.0]
    assert np.allclose(rpy_matrix(*rpy), quaternion_matrix(*OPTICAL_IN_CAMERA_LINK_XYZW),
                       atol=1e-12)


@pytest.mark.parametrize('mount', MOUNTS, ids=lambda m: '%gm_%gdeg' % (m.height_m, m.pitch_deg))
def test_mast_reaches_up_to_the_camera(mount):
    bottom, top = mast(ET.fromstring(robot_urdf(TEMPLATE, mount)))
    assert bottom == pytest.approx(mast(ET.fromstring(TEMPLATE))[0])
    assert top == pytest.approx(mount.height_m - MAST_GAP_M)


def test_a_camera_on_the_body_has_no_mast():
    assert mast(ET.fromstring(robot_urdf(TEMPLATE, CameraMount(0.09, 25.0)))) is None


def test_keeps_the_comments():
    assert robot_urdf(TEMPLATE, CameraMount(0.3, 10.0)).startswith(
        TEMPLATE[:TEMPLATE.index('<robot')])


def test_a_template_without_camera_joint_is_refused():
    with pytest.raises(ValueError, match='camera_joint'):
        robot_urdf('<robot name="r"><link name="base_link"/></robot>', CameraMount(0.25, 25.0))


def test_mount_params_are_the_simulators():
    from can_seeker.sim.simulation import PARAMS
    by_name = {spec.name: spec for spec in PARAMS}
    for spec in MOUNT_PARAMS:
        assert by_name[spec.name] is spec


def test_invalid_mount_params_fall_back_to_the_defaults():
    warnings = []
    mount = mount_from_params({'~camera_height': 0.05, '~camera_pitch_deg': '31.5'}.get,
                              warnings.append)
    assert mount == CameraMount(0.25, 31.5)
    assert len(warnings) == 1 and 'camera_height' in warnings[0]


def run_tool(*args):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        robot_description.main(list(args) + ['--template', str(URDF)])
    return out.getvalue(), err.getvalue()


def test_tool_prints_the_mounted_urdf():
    out, err = run_tool('--camera-height', '0.35', '--camera-pitch-deg', '35')
    assert out == robot_urdf(TEMPLATE, CameraMount(0.35, 35.0))
    assert err == ''


def test_tool_warns_and_uses_the_default_like_the_simulator():
    out, err = run_tool('--camera-height', '2.0', '--camera-pitch-deg', '35')
    assert out == robot_urdf(TEMPLATE, CameraMount(0.25, 35.0))
    assert 'camera_height' in err and 'using the default 0.25' in err


@pytest.mark.parametrize('mount', MOUNTS[:2], ids=lambda m: '%gm_%gdeg' % (m.height_m, m.pitch_deg))
def test_simulator_loads_the_robot_with_its_mount(mount):
    with World(str(URDF), CameraSpec(32, 24, 45.0, mount), renderer='tiny') as world:
        client, robot = world._client, world._robot
        links = {client.getJointInfo(robot, joint)[12].decode(): joint
                 for joint in range(client.getNumJoints(robot))}
        for _ in range(120):
            world.step()
        state = client.getLinkState(robot, links['camera_link'], computeForwardKinematics=True)
        position, rotation = world.camera_pose()
        assert state[4] == pytest.approx(tuple(position), abs=1e-6)
        assert np.allclose(quaternion_matrix(*state[5]), rotation, atol=1e-6)


def test_links_take_the_frame_names_and_the_prefix():
    names = {'base_link': 'robot1/base', 'camera_link': 'robot1/cam',
             'camera_optical_frame': 'robot1/cam_optical'}
    robot = ET.fromstring(robot_urdf(TEMPLATE, CameraMount(0.3, 20.0), names, 'robot1/'))
    links = {link.get('name') for link in robot.iter('link')}
    assert links == {'robot1/base', 'robot1/cam', 'robot1/cam_optical', 'robot1/left_wheel',
                     'robot1/right_wheel', 'robot1/front_caster', 'robot1/rear_caster'}
    ends = {end.get('link') for joint in robot.iter('joint') for end in joint
            if end.tag in ('parent', 'child')}
    assert ends == links
    xyz, _ = joint_origin(robot, 'camera_joint')
    assert xyz == pytest.approx([0.12, 0.0, 0.3])
    assert mast(ET.fromstring(robot_urdf(TEMPLATE, CameraMount(0.3, 20.0)))) is not None
    assert robot.find("link[@name='robot1/base']/visual[@name='camera_mast']") is not None


def test_tool_names_the_links():
    out, _ = run_tool('--base-frame', 'r/base_link', '--camera-frame', 'r/camera_link',
                      '--optical-frame', 'r/camera_optical_frame', '--link-prefix', 'r/')
    assert out == robot_urdf(TEMPLATE, CameraMount(0.25, 25.0),
                             {'base_link': 'r/base_link', 'camera_link': 'r/camera_link',
                              'camera_optical_frame': 'r/camera_optical_frame'}, 'r/')
