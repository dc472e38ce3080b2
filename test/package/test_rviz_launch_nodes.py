"""rviz.launch beside a real robot: robot_state:=false starts rviz alone, so no second
robot_state_publisher and no joint_state_publisher holding the wheels at 0 join the robot's."""
import pathlib
import subprocess

LAUNCH = pathlib.Path(__file__).resolve().parents[2] / 'launch' / 'rviz.launch'


def nodes(*args):
    result = subprocess.run(['roslaunch', '--nodes', str(LAUNCH)] + list(args),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, check=False)
    assert result.returncode == 0, result.stdout
    return set(result.stdout.split())


def test_rviz_brings_the_robot_models_tf_by_default():
    assert nodes() == {'/rviz', '/robot_state_publisher', '/joint_state_publisher'}


def test_beside_a_robot_rviz_comes_alone():
    assert nodes('robot_state:=false') == {'/rviz'}
