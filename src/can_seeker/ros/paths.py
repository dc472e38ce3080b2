"""Where the installed can_seeker package keeps its files (rospkg: the package path as ROS
finds it, in a devel space or an install space). The simulator gets these paths passed in."""
import os

import rospkg

PACKAGE = 'can_seeker'


def package_dir() -> str:
    """The share folder of the installed can_seeker package."""
    return rospkg.RosPack().get_path(PACKAGE)


def urdf_path() -> str:
    """The robot URDF (also the robot_description)."""
    return os.path.join(package_dir(), 'urdf', 'can_seeker_robot.urdf')


def robots_dir() -> str:
    """The package's robot profiles."""
    return os.path.join(package_dir(), 'config', 'robots')


def worlds_dir() -> str:
    """The package's world files."""
    return os.path.join(package_dir(), 'worlds')
