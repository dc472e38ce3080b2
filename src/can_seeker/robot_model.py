"""The robot's URDF for a camera mount: one model for robot_description and the simulator.

``urdf/can_seeker_robot.urdf`` describes the robot with the camera at the default mount. The
simulator loads, and robot_description holds, that file with the actual mount applied by
:func:`robot_urdf`: the ``camera_joint`` origin is the :class:`CameraMount`'s own translation and
rotation (the same values the simulator renders from and broadcasts as TF), the
``camera_optical_joint`` rotation is :data:`OPTICAL_IN_CAMERA_LINK_XYZW` and the mast under the
camera (the base_link visual named ``camera_mast``) reaches up to the camera. Links can be
renamed to the frames the nodes use (``~base_frame``, ``~camera_frame``, ``~optical_frame``) and
the others prefixed (``robot1/left_wheel``). No rospy here.
"""
import math
import re
import xml.etree.ElementTree as ET
from typing import Mapping, Optional, Sequence, Tuple

from can_seeker.camera_mount import OPTICAL_IN_CAMERA_LINK_XYZW, CameraMount

CAMERA_JOINT = 'camera_joint'
OPTICAL_JOINT = 'camera_optical_joint'
MAST_VISUAL = 'camera_mast'
MAST_GAP_M = 0.01
"""Gap between the top of the mast and camera_link's origin (m): half the camera housing."""


def rpy_from_quaternion(x: float, y: float, z: float, w: float) -> Tuple[float, float, float]:
    """URDF roll, pitch, yaw (fixed axes: R = Rz(yaw) Ry(pitch) Rx(roll)) of a unit quaternion."""
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


def _numbers(values: Sequence[float]) -> str:
    """URDF number list: each number's shortest text that reads back exactly, no negative
    zero."""
    return ' '.join(repr(float(value) + 0.0) for value in values)


def _parse_numbers(text: str) -> Tuple[float, ...]:
    return tuple(float(value) for value in text.split())


def _find(robot: ET.Element, path: str, what: str) -> ET.Element:
    element = robot.find(path)
    if element is None:
        raise ValueError('the robot URDF has no %s' % what)
    return element


def _set_origin(robot: ET.Element, joint: str, xyz: Sequence[float],
                rotation_xyzw: Sequence[float]):
    origin = _find(robot, "joint[@name='%s']/origin" % joint, '%s origin' % joint)
    origin.set('xyz', _numbers(xyz))
    origin.set('rpy', _numbers(rpy_from_quaternion(*rotation_xyzw)))


def apply_mount(robot: ET.Element, mount: CameraMount):
    """Set the camera joints' origins from ``mount`` and fit the camera mast to its height, in
    place."""
    _set_origin(robot, CAMERA_JOINT, mount.translation_m, mount.rotation_xyzw)
    _set_origin(robot, OPTICAL_JOINT, (0.0, 0.0, 0.0), OPTICAL_IN_CAMERA_LINK_XYZW)
    parent = _find(robot, "joint[@name='%s']/parent" % CAMERA_JOINT, 'camera_joint parent')
    link = _find(robot, "link[@name='%s']" % parent.get('link'), 'camera_joint parent link')
    mast = link.find("visual[@name='%s']" % MAST_VISUAL)
    if mast is None:
        return
    mast_origin = _find(mast, 'origin', 'camera_mast origin')
    cylinder = _find(mast, 'geometry/cylinder', 'camera_mast cylinder')
    x, y, z = _parse_numbers(mast_origin.get('xyz'))
    bottom_m = z - float(cylinder.get('length')) / 2.0
    top_m = mount.translation_m[2] - MAST_GAP_M
    if top_m <= bottom_m:
        link.remove(mast)
        return
    mast_origin.set('xyz', _numbers((x, y, (bottom_m + top_m) / 2.0)))
    cylinder.set('length', _numbers((top_m - bottom_m,)))


def rename_links(robot: ET.Element, names: Mapping[str, str], prefix: str = ''):
    """Rename links in place: those in ``names`` to their value, every other one to ``prefix``
    + its name; the joints' parent and child follow."""
    def new_name(name):
        return names.get(name, prefix + name)
    for link in robot.iter('link'):
        link.set('name', new_name(link.get('name')))
    for joint in robot.iter('joint'):
        for end in ('parent', 'child'):
            element = joint.find(end)
            element.set('link', new_name(element.get('link')))


def robot_urdf(template: str, mount: CameraMount, link_names: Optional[Mapping[str, str]] = None,
               link_prefix: str = '') -> str:
    """The URDF text ``template`` (the robot at any camera mount) with ``mount`` applied and
    its links renamed (:func:`rename_links`: ``link_names`` such as {'base_link':
    'robot1/base_link'}, ``link_prefix`` for the links not in it).

    Comments and every other element are kept; raises ValueError when the template has no
    camera joints.
    """
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    robot = ET.fromstring(template, parser=parser)
    apply_mount(robot, mount)
    if link_names or link_prefix:
        rename_links(robot, link_names or {}, link_prefix)
    start = re.search(r'<robot[\s>]', template)
    head = template[:start.start()] if start else '<?xml version="1.0"?>\n'
    return head + ET.tostring(robot, encoding='unicode') + '\n'

