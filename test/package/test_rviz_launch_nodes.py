"""rviz.launch beside a real robot: robot_state:=false starts rviz alone, so no second
robot_state_publisher and no joint_state_publisher holding the wheels at 0 join the robot's."""
from launch_query import launched_nodes


def nodes(*args):
    return launched_nodes('rviz.launch', *args)


def test_rviz_brings_the_robot_models_tf_by_default():
    assert nodes() == {'/rviz', '/robot_state_publisher', '/joint_state_publisher'}


def test_beside_a_robot_rviz_comes_alone():
    assert nodes('robot_state:=false') == {'/rviz'}
