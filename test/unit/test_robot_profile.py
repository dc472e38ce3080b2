"""Robot profiles: every shipped profile loads and its node sections are what its figures give;
bad profiles are refused with the reason; the default profile is the built-in robot; a profile
builds the URDF, the simulator's configuration and a pybullet robot that drives as it says."""
import math
import pathlib
import xml.etree.ElementTree as ET

import pytest
import yaml

from can_seeker.camera_geometry import camera_pose_from_mount, floor_point, \
    intrinsics_from_vertical_fov
from can_seeker.camera_mount import CAMERA_FORWARD_M, CameraMount
from can_seeker.control.controller import PARAMS as CONTROL_PARAMS
from can_seeker.params import defaults
from can_seeker.robot_model import robot_urdf
from can_seeker.robot_profile import (ProfileError, camera_mount, check_node_sections,
                                      launch_arguments, load_profile, node_params,
                                      profile_from_dict)
from can_seeker.sim.scene import ROBOT_RADIUS_M, WHEEL_RADIUS_M, WHEEL_SEPARATION_M
from can_seeker.sim.simulation import PARAMS as SIM_PARAMS, camera_spec, checked_config, \
    lidar_spec
from can_seeker.sim.world import World
from can_seeker.tools.evaluate import scaled_time_limit
from can_seeker.tools.docs import node_params as declared_node_params
from urdf_checks import joint_origin

ROOT = pathlib.Path(__file__).resolve().parents[2]
ROBOTS = ROOT / 'config' / 'robots'
URDF = ROOT / 'urdf' / 'can_seeker_robot.urdf'
SHIPPED = sorted(path.stem for path in ROBOTS.glob('*.yaml'))
SIM = {spec.name: spec.default for spec in SIM_PARAMS}


def load(name):
    return load_profile(name, [str(ROBOTS)])


def raw(name):
    return yaml.safe_load((ROBOTS / (name + '.yaml')).read_text())


def test_the_required_profiles_ship():
    assert set(SHIPPED) >= {'default', 'create2', 'turtlebot3_burger', 'turtlebot3_waffle_pi'}


@pytest.mark.parametrize('name', SHIPPED)
def test_every_profile_loads_and_its_node_sections_are_its_figures(name):
    profile = load(name)
    data = raw(name)
    for node, values in node_params(profile).items():
        for key, value in values.items():
            assert data[node][key] == pytest.approx(value), '%s %s/%s' % (name, node, key)
    assert profile.footprint_radius_m <= profile.body_radius_m + 1e-9


@pytest.mark.parametrize('name', SHIPPED)
def test_node_sections_hold_only_parameters_the_nodes_declare(name):
    declared = {script: {spec.name for spec in params}
                for script, params in declared_node_params(ROOT)}
    data = raw(name)
    for node in ('image_converter', 'obstacle_scan', 'can_stopper'):
        assert set(data.get(node, ())) <= declared[node], '%s: %s' % (
            name, set(data.get(node, ())) - declared[node])


@pytest.mark.parametrize('name', SHIPPED)
def test_the_camera_mount_is_no_node_parameter_of_a_profile(name):
    """The nodes take the mount from TF (robot_description from the profile): no node section
    holds a copy that could disagree with it."""
    data = raw(name)
    for node in ('image_converter', 'obstacle_scan', 'can_stopper'):
        assert not {'camera_height', 'camera_pitch_deg', 'camera_x'} & set(data.get(node, ()))


def test_the_default_profile_is_the_built_in_robot():
    profile = load('default')
    assert profile.body_radius_m == ROBOT_RADIUS_M
    assert profile.wheel_separation_m == WHEEL_SEPARATION_M
    assert profile.wheel_radius_m == WHEEL_RADIUS_M
    assert camera_mount(profile) == CameraMount(SIM['camera_height'], SIM['camera_pitch_deg'],
                                                CAMERA_FORWARD_M)
    assert profile.camera.vertical_fov_deg == SIM['fov_deg']
    lidar = profile.lidar
    assert (lidar.beams, lidar.range_min_m, lidar.range_max_m, lidar.height_m, lidar.rate_hz) \
        == (SIM['scan_beams'], SIM['scan_range_min'], SIM['scan_range_max'], SIM['scan_height'],
            SIM['scan_rate'])
    control = {spec.name: spec.default for spec in CONTROL_PARAMS}
    for key, value in node_params(profile)['can_stopper'].items():
        assert control[key] == pytest.approx(value), key


def test_the_default_profile_builds_the_template_robot():
    template = URDF.read_text()
    mount = CameraMount(0.25, 25.0)
    plain = ET.fromstring(robot_urdf(template, mount))
    built = ET.fromstring(robot_urdf(template, mount, profile=load('default')))
    for joint in ('left_wheel_joint', 'right_wheel_joint', 'front_caster_joint',
                  'rear_caster_joint', 'camera_joint'):
        assert joint_origin(built, joint)[0] == pytest.approx(joint_origin(plain, joint)[0]), joint
    for path in ("link[@name='base_link']/collision/geometry/cylinder",
                 "link[@name='base_link']/visual/geometry/cylinder"):
        assert {key: float(value) for key, value in built.find(path).attrib.items()} \
            == pytest.approx({key: float(value) for key, value in plain.find(path).attrib.items()})


def _broken(**changes):
    data = raw('create2')
    for path, value in changes.items():
        section = data
        keys = path.split('.')
        for key in keys[:-1]:
            section = section[key]
        if value is None:
            del section[keys[-1]]
        else:
            section[keys[-1]] = value
    return data


@pytest.mark.parametrize('changes,message', [
    ({'robot_profile.wheel_radius_m': None}, 'wheel_radius_m is missing'),
    ({'robot_profile.max_linear_mps': 5.0}, 'max_linear_mps = 5.0 is outside'),
    ({'robot_profile.camera.pitch_deg': 'down'}, 'pitch_deg must be a number'),
    ({'robot_profile.bumper': 'yes'}, 'bumper must be true or false'),
    ({'robot_profile.wheel_separation_m': 0.5}, 'stick out of the body'),
    ({'robot_profile.footprint_m': {'x_min': -0.3, 'x_max': 0.1, 'y_min': -0.1, 'y_max': 0.1}},
     'does not hold the footprint'),
    ({'robot_profile.lidar': {'range_min_m': 1.0, 'range_max_m': 0.5, 'rate_hz': 5,
                              'field_deg': 360, 'beams': 360, 'height_m': 0.1}},
     'range_max_m 0.5 is not above'),
    ({'robot_profile.topics': {'camera': 'c', 'laser': 'l'}}, 'topics may name only'),
])
def test_bad_profiles_are_refused_with_the_reason(changes, message):
    with pytest.raises(ProfileError, match=message):
        profile_from_dict(_broken(**changes), 'create2')


def test_a_node_section_that_disagrees_with_the_figures_is_refused():
    data = _broken(**{'can_stopper.robot_radius': 0.1, 'obstacle_scan.robot_height': None})
    with pytest.raises(ProfileError) as error:
        check_node_sections(data, profile_from_dict(data, 'create2'))
    assert 'can_stopper/robot_radius is 0.1, the figures give 0.17' in str(error.value)
    assert 'obstacle_scan/robot_height missing (should be 0.092)' in str(error.value)


def test_a_null_is_refused_since_the_parameter_server_holds_none(tmp_path):
    path = tmp_path / 'robot.yaml'
    path.write_text((ROBOTS / 'create2.yaml').read_text().replace('lidar: false', 'lidar: null'))
    with pytest.raises(ProfileError, match='robot_profile/lidar empty'):
        load_profile(str(path))


def test_an_unknown_profile_names_where_it_looked():
    with pytest.raises(ProfileError, match='no robot profile .nosuch. \\(looked in .*robots'):
        load('nosuch')


def test_the_launch_line_has_the_drivers_topics():
    line = launch_arguments(load('create2'))
    assert 'robot:=create2' in line and 'camera:=create1/camera' in line
    assert 'cmd_vel:=create1/cmd_vel' in line and 'base_frame:=base_footprint' in line


def test_a_pi_camera_profile_reads_raspicam_nodes_image_topic():
    """raspicam_node publishes raspicam_node/image/compressed, not image_raw/compressed."""
    for name in ('turtlebot3_waffle_pi', 'turtlebot3_burger'):
        line = launch_arguments(load(name))
        assert 'camera:=raspicam_node' in line and 'image:=image ' in line
        assert 'image_transport:=compressed' in line


def test_a_footprint_profile_builds_its_box_wheels_casters_and_camera():
    profile = load('turtlebot3_waffle_pi')
    robot = ET.fromstring(robot_urdf(URDF.read_text(), camera_mount(profile), profile=profile))
    box = robot.find("link[@name='base_link']/collision/geometry/box")
    assert [float(side) for side in box.get('size').split()] == pytest.approx(
        [0.266, 0.266, 0.104 - 0.015])
    left, right = (joint_origin(robot, side + '_wheel_joint')[0] for side in ('left', 'right'))
    assert left == pytest.approx([0.0, 0.144, 0.033])
    assert right == pytest.approx([0.0, -0.144, 0.033])
    front = joint_origin(robot, 'front_caster_joint')[0]
    rear = joint_origin(robot, 'rear_caster_joint')[0]
    assert -0.197 < rear[0] < 0.0 < front[0] < 0.069
    camera_xyz, camera_rpy = joint_origin(robot, 'camera_joint')
    assert camera_xyz == pytest.approx([0.076, 0.0, 0.102])
    assert camera_rpy == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)


@pytest.mark.parametrize('name', ['turtlebot3_burger', 'turtlebot3_waffle_pi'])
def test_a_level_camera_still_sees_the_floor_below_the_horizon(name):
    """Pitch 0 (the TurtleBot3's Pi camera looks level): rays below the image centre meet the
    floor ahead, farther the nearer they come to the horizon; the centre row never does."""
    profile = load(name)
    intrinsics = intrinsics_from_vertical_fov(320, 240, profile.camera.vertical_fov_deg)
    pose = camera_pose_from_mount(camera_mount(profile))
    bottom = floor_point(pose, intrinsics, 160.0, 239.5)
    near_horizon = floor_point(pose, intrinsics, 160.0, 125.0)
    assert bottom is not None and near_horizon is not None
    assert profile.camera.forward_m < bottom[0] < near_horizon[0]
    assert bottom[0] == pytest.approx(profile.camera.forward_m + profile.camera.height_m
                                      / math.tan(math.radians(24.4)), rel=0.02)
    assert floor_point(pose, intrinsics, 160.0, 119.5) is None


def test_the_simulator_takes_the_camera_and_lidar_from_the_profile():
    warnings = []
    config = checked_config(defaults(SIM_PARAMS, {'robot': 'turtlebot3_burger'}),
                            warnings.append, (), [str(ROBOTS)])
    assert not warnings
    spec = camera_spec(config)
    assert spec.fov_deg == 48.8
    assert spec.mount == CameraMount(0.102, 0.0, 0.076)
    lidar = lidar_spec(config)
    assert (lidar.beams, lidar.range_max_m, lidar.height_m, config.scan_rate) \
        == (360, 3.5, 0.181, 5.0)
    assert config.profile.name == 'turtlebot3_burger'


def test_a_profile_without_lidar_turns_the_simulated_lidar_off_and_a_bad_one_is_warned():
    config = checked_config(defaults(SIM_PARAMS, {'robot': 'create2'}), [].append, (),
                            [str(ROBOTS)])
    assert config.scan_rate == 0.0
    warnings = []
    config = checked_config(defaults(SIM_PARAMS, {'robot': 'nosuch'}), warnings.append, (),
                            [str(ROBOTS)])
    assert config.profile is None and config.scan_rate == SIM['scan_rate']
    assert any('parameter ~robot: no robot profile' in text for text in warnings)


def test_a_slow_robot_gets_a_longer_time_limit():
    assert scaled_time_limit(0.4) == pytest.approx(90.0)
    assert scaled_time_limit(0.5) == pytest.approx(90.0)
    assert scaled_time_limit(0.22) == pytest.approx(90.0 * 0.4 / 0.22)


def test_the_simulated_waffle_pi_stands_level_and_drives_at_the_commanded_speed():
    profile = load('turtlebot3_waffle_pi')
    config = checked_config(defaults(SIM_PARAMS, {'robot': 'turtlebot3_waffle_pi'}), [].append,
                            (), [str(ROBOTS)])
    with World(str(URDF), camera_spec(config), renderer='tiny', profile=profile) as world:
        for _ in range(120):
            world.step()
        rest = world.robot_state()
        assert abs(rest.position[2]) < 0.003
        x, y, z, w = rest.orientation_xyzw
        assert math.degrees(2.0 * math.asin(min(1.0, math.hypot(x, y)))) < 1.0
        world.set_twist(0.2, 0.0)
        for _ in range(240):
            world.step()
        assert world.robot_state().linear_velocity[0] == pytest.approx(0.2, rel=0.05)


def test_robot_params_names_a_profile_file_by_its_absolute_path(tmp_path, monkeypatch, capsys):
    """robot.launch finds a profile outside config/robots/ only by an absolute path."""
    from can_seeker.tools.robot_params import main as robot_params
    mine = tmp_path / 'my_waffle.yaml'
    mine.write_text((ROBOTS / 'turtlebot3_waffle_pi.yaml').read_text())
    monkeypatch.chdir(tmp_path)
    robot_params(['my_waffle.yaml'])
    assert 'robot.launch robot:=%s ' % mine in capsys.readouterr().out
    robot_params(['create2'])
    assert 'robot.launch robot:=create2 ' in capsys.readouterr().out
