"""robot_description: the robot's URDF for a camera mount, on standard output.

``rosrun can_seeker robot_description --camera-height 0.3 --camera-pitch-deg 30`` prints
``urdf/can_seeker_robot.urdf`` with that mount applied (:mod:`can_seeker.robot_model`), the model
the simulator loads for the same ``~camera_height`` and ``~camera_pitch_deg``. Invalid values are
replaced by their defaults with a warning on standard error, as the simulator does. Launch files
set the parameter with it: ``<param name="robot_description" command="...">``. ``--base-frame``,
``--camera-frame`` and ``--optical-frame`` name the links of those frames as the simulator's
parameters do; ``--link-prefix`` goes before the names of the other links (wheels, casters).
``--robot NAME`` builds the robot of a profile (config/robots/NAME.yaml or a path: its body,
wheels and camera mount; the mount options are then ignored), as the simulator's ``~robot``.
"""
import argparse
import os
import sys

from can_seeker.camera_mount import MOUNT_PARAMS, mount_from_params
from can_seeker.frames import BASE_FRAME, CAMERA_FRAME, OPTICAL_FRAME
from can_seeker.robot_model import robot_urdf
from can_seeker.robot_profile import ProfileError, camera_mount, load_profile


def package_dir() -> str:
    import rospkg  # only when a file of the package is needed: finding it crawls ROS_PACKAGE_PATH
    return rospkg.RosPack().get_path('can_seeker')


def package_template() -> str:
    return os.path.join(package_dir(), 'urdf', 'can_seeker_robot.urdf')


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    for spec in MOUNT_PARAMS:
        parser.add_argument('--' + spec.name.replace('_', '-'), default=spec.default,
                            help='%s; default %s' % (spec.description, spec.default))
    for spec in (BASE_FRAME, CAMERA_FRAME, OPTICAL_FRAME):
        parser.add_argument('--' + spec.name.replace('_', '-'), default=spec.default,
                            help='name of the link %s (%s)' % (spec.default, spec.doc))
    parser.add_argument('--link-prefix', default='', help='prefix of the other links\' names '
                        '(wheels, casters), e.g. robot1/')
    parser.add_argument('--robot', default='', help='robot profile: a name in the package\'s '
                        'config/robots/ or a YAML path; empty: the template\'s robot with the '
                        'mount options')
    parser.add_argument('--template', help="the robot's URDF at the default mount; default: "
                        'urdf/can_seeker_robot.urdf of the can_seeker package')
    args = parser.parse_args(argv)
    values = vars(args)
    mount = mount_from_params(lambda name, default: values.get(name.lstrip('~'), default),
                              lambda text: print('robot_description: ' + text, file=sys.stderr))
    profile = None
    if args.robot:
        robots_dir = (os.path.join(package_dir(), 'config', 'robots')
                      if not os.path.isfile(args.robot) else os.path.dirname(args.robot))
        try:
            profile = load_profile(args.robot, [robots_dir])
        except ProfileError as error:
            sys.exit('robot_description: %s' % error)
        mount = camera_mount(profile)
    with open(args.template or package_template()) as template:
        sys.stdout.write(robot_urdf(
            template.read(), mount,
            {spec.default: values[spec.name] for spec in (BASE_FRAME, CAMERA_FRAME, OPTICAL_FRAME)},
            args.link_prefix, profile))
