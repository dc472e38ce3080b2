"""robot.launch gives each node the profile's values over its launch defaults, and the user's
params file over the profile: what roslaunch would set (--dump-params), no master needed."""
import os
import pathlib
import signal
import subprocess

import pytest

from can_seeker.tools.closed_loop import free_port
from launch_query import dumped_params

REPO = pathlib.Path(__file__).resolve().parents[2]


def dump(*args):
    return dumped_params('robot.launch', *args)


def test_the_profile_wins_over_the_node_defaults():
    params = dump('robot:=turtlebot3_burger')
    assert params['/can_stopper/robot_radius'] == pytest.approx(0.124)
    assert params['/obstacle_scan/robot_radius'] == pytest.approx(0.124)
    assert params['/can_stopper/max_linear'] == pytest.approx(0.22)
    assert params['/obstacle_scan/robot_height'] == pytest.approx(0.15)


def test_no_node_gets_a_camera_mount_parameter():
    """The mount reaches the nodes through TF only (the robot's robot_state_publisher)."""
    params = dump('robot:=turtlebot3_burger')
    for node in ('image_converter', 'obstacle_scan', 'can_stopper'):
        for name in ('camera_height', 'camera_pitch_deg', 'camera_x'):
            assert '/%s/%s' % (node, name) not in params


def test_the_users_params_win_over_the_profile(tmp_path):
    user = tmp_path / 'mine.yaml'
    user.write_text('can_stopper:\n  max_linear: 0.15\n  stop_distance: 0.4\n'
                    'obstacle_scan:\n  robot_radius: 0.3\n')
    params = dump('robot:=turtlebot3_burger', 'params:=%s' % user)
    assert params['/can_stopper/max_linear'] == pytest.approx(0.15)
    assert params['/can_stopper/stop_distance'] == pytest.approx(0.4)
    assert params['/obstacle_scan/robot_radius'] == pytest.approx(0.3)
    assert params['/can_stopper/robot_radius'] == pytest.approx(0.124)


def test_the_launch_wires_the_robots_topics_and_frames_and_sets_no_sim_time():
    params = dump('robot:=create2', 'base_frame:=base_footprint', 'odom:=create1/odom',
                  'scan:=scan')
    assert '/use_sim_time' not in params
    assert not any(key.startswith('/sim/') for key in params)
    assert params['/can_stopper/lockstep'] is False
    assert params['/can_stopper/base_frame'] == 'base_footprint'
    assert params['/obstacle_scan/scan_frame'] == 'base_footprint'
    assert params['/can_stopper/odom_topic'] == 'create1/odom'
    assert params['/can_stopper/scan_topics'] == 'camera_scan scan'
    assert params['/can_stopper/robot_radius'] == pytest.approx(0.17)


def test_the_example_params_file_loads():
    params = dump('robot:=create2', 'params:=%s' % (REPO / 'config' / 'robot.yaml'))
    assert params['/can_stopper/stop_distance'] == pytest.approx(0.3)


def image_remaps(*args):
    """Where robot.launch points each image node's ``image`` (roslaunch's own loader)."""
    import roslaunch.config
    config = roslaunch.config.load_config_default(
        [(str(REPO / 'launch' / 'robot.launch'), list(args))], None)
    return {node.name: dict(node.remap_args)['image'] for node in config.nodes
            if node.name in ('image_converter', 'obstacle_scan')}


def test_the_image_topic_follows_the_camera_and_image_arguments():
    assert image_remaps() == {'image_converter': 'camera/image_raw',
                              'obstacle_scan': 'camera/image_raw'}
    pi = image_remaps('robot:=turtlebot3_waffle_pi', 'camera:=raspicam_node', 'image:=image',
                      'image_transport:=compressed')
    assert pi == {'image_converter': 'raspicam_node/image', 'obstacle_scan': 'raspicam_node/image'}


def test_the_profile_is_checked_before_any_node_starts(tmp_path):
    """A profile robot_params refuses stops roslaunch with its reason, as in the simulator."""
    good = (REPO / 'config' / 'robots' / 'turtlebot3_waffle_pi.yaml').read_text()
    assert dump('robot:=turtlebot3_waffle_pi')['/robot_profile_name'] == 'turtlebot3_waffle_pi'
    small = good.replace('body_radius_m: &body_radius_m 0.238',
                         'body_radius_m: &body_radius_m 0.1')
    assert small != good
    bad = tmp_path / 'small_waffle.yaml'
    bad.write_text(small)
    # roslaunch itself, on a port of its own: it exits while loading, before starting a master
    # (if it did start one, its whole process group goes at the time-out)
    launch = subprocess.Popen(['roslaunch', '-p', str(free_port()),
                               str(REPO / 'launch' / 'robot.launch'), 'robot:=%s' % bad],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              universal_newlines=True, start_new_session=True)
    try:
        output, _ = launch.communicate(timeout=60)
    finally:
        if launch.poll() is None:
            os.killpg(launch.pid, signal.SIGKILL)
            launch.wait()
    assert launch.returncode == 1, output
    assert 'body_radius_m 0.1 does not hold the footprint' in output
    assert 'started roslaunch server' not in output
