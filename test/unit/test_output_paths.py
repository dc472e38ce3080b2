"""The tools' default output folders: in the workspace's home when there is one, else in the
ROS home, else in ~/.ros; never relative to the working directory."""
import os

from can_seeker.output_paths import default_output_dir, output_home


def test_the_workspace_home_comes_first():
    environ = {'CAN_SEEKER_HOME': '/tmp/ws_home', 'ROS_HOME': '/tmp/ros', 'HOME': '/home/me'}
    assert default_output_dir('demo_output', environ) == '/tmp/ws_home/demo_output'


def test_without_a_workspace_home_the_ros_home_holds_a_can_seeker_folder():
    environ = {'CAN_SEEKER_HOME': '', 'ROS_HOME': '/tmp/ros', 'HOME': '/home/me'}
    assert default_output_dir('sweep', environ) == '/tmp/ros/can_seeker/sweep'


def test_without_either_it_is_where_ros_keeps_its_logs():
    assert output_home({'HOME': '/home/me'}) == '/home/me/.ros/can_seeker'


def test_a_relative_home_does_not_depend_on_the_working_directory_later():
    folder = default_output_dir('bag_detect', {'CAN_SEEKER_HOME': 'relative/home'})
    assert os.path.isabs(folder) and folder.endswith(os.path.join('relative', 'home',
                                                                  'bag_detect'))
