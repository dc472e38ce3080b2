"""robot_params: what a robot profile gives the nodes, and the robot.launch line for its driver.

``rosrun can_seeker robot_params create2`` checks config/robots/create2.yaml (or a path) and
prints its node sections (the parameters robot.launch loads for image_converter, obstacle_scan
and can_stopper) and the ``roslaunch can_seeker robot.launch ...`` line with the driver's
topics from the profile's ``topics`` (roslaunch takes remappings from arguments only).
Exits 1 with the reason when the profile is wrong. ``--check`` prints only the profile's name:
robot.launch sets its ``robot_profile_name`` parameter from it, so roslaunch stops with the reason
before any node starts on a wrong profile.
"""
import argparse
import os
import sys

import yaml

from can_seeker.robot_profile import ProfileError, launch_arguments, load_profile, node_params


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('robot', help="a name in the package's config/robots/ or a YAML path")
    parser.add_argument('--check', action='store_true',
                        help="print only the profile's name (robot.launch's robot_profile_name "
                        "parameter), or exit 1 with the reason it is wrong")
    args = parser.parse_args(argv)
    search = []
    robot = os.path.abspath(args.robot) if os.path.isfile(args.robot) else None
    if robot is None:
        import rospkg  # only for a name: finding the package crawls ROS_PACKAGE_PATH
        search = [os.path.join(rospkg.RosPack().get_path('can_seeker'), 'config', 'robots')]
    try:
        profile = load_profile(args.robot, search)
    except ProfileError as error:
        sys.exit('robot_params: %s' % error)
    if args.check:
        sys.stdout.write(profile.name)
        return
    print('# node parameters from the figures of %s' % profile.name)
    sys.stdout.write(yaml.safe_dump(node_params(profile), default_flow_style=False))
    print('# bring it up:\n# %s' % launch_arguments(profile, robot))
