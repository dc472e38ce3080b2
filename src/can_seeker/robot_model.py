"""The robot's URDF for a camera mount: one model for robot_description and the simulator.

``urdf/can_seeker_robot.urdf`` describes the robot with the camera at the default mount. The
simulator loads, and robot_description holds, that file with the actual mount applied by
:func:`robot_urdf`: the ``camera_joint`` origin is the :class:`CameraMount`'s own translation and
rotation (the same values the simulator renders from and broadcasts as TF), the
``camera_optical_joint`` rotation is :data:`OPTICAL_IN_CAMERA_LINK_XYZW` and the mast under the
camera (the base_link visual named ``camera_mast``) reaches up to the camera. Links can be
renamed to the frames the nodes use (``~base_frame``, ``~camera_frame``, ``~optical_frame``) and
the others prefixed (``robot1/left_wheel``). A :class:`~can_seeker.robot_profile.RobotProfile`
gives the model its body (disc or footprint box, height, mass), wheels and casters
(:func:`apply_body`). No rospy here.
"""
import math
import re
import xml.etree.ElementTree as ET
from typing import Mapping, Optional, Sequence, Tuple

from can_seeker.camera_mount import OPTICAL_IN_CAMERA_LINK_XYZW, CameraMount
from can_seeker.robot_profile import RobotProfile

CAMERA_JOINT = 'camera_joint'
OPTICAL_JOINT = 'camera_optical_joint'
MAST_VISUAL = 'camera_mast'
MAST_GAP_M = 0.01
"""Gap between the top of the mast and camera_link's origin (m): half the camera housing."""
MAST_BEHIND_CAMERA_M = 0.03
"""The mast stands this far behind camera_link's origin (m)."""
BODY_BOTTOM_M = 0.015
"""Height of the body's underside above the floor (m): the casters' top."""
CASTER_INSET_M = 0.035
"""The casters sit this far inside the body's front and back edges (m)."""
CASTER_RESTING_Z_M = 0.015
CASTER_FLOATING_Z_M = 0.0155
"""The caster on the centre of mass's side of the axle rests on the floor; the other floats
0.5 mm above it and only catches a hard pitch."""
COM_AHEAD_M = 0.01
"""The centre of mass lies this far ahead of the body's centre (m)."""


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


def _set_xyz(element: ET.Element, xyz: Sequence[float]):
    _find(element, 'origin', 'origin').set('xyz', _numbers(xyz))


def apply_body(robot: ET.Element, profile: RobotProfile):
    """Give the model ``profile``'s body (a cylinder of body_radius_m, or the footprint box,
    from BODY_BOTTOM_M up to body_height_m), mass, wheels and casters, in place; the camera mast
    stands on the body behind the camera (:func:`apply_mount` fits its height)."""
    base = _find(robot, "link[@name='base_link']", 'base_link')
    bottom_m, top_m = BODY_BOTTOM_M, profile.body_height_m
    if top_m <= bottom_m + 0.01:
        raise ValueError('body_height_m %r leaves no body above the casters' % top_m)
    if profile.footprint_m is None:
        centre_x, front_x, back_x = 0.0, profile.body_radius_m, -profile.body_radius_m
        size = None
    else:
        x_min, x_max, y_min, y_max = profile.footprint_m
        centre_x, front_x, back_x = (x_min + x_max) / 2.0, x_max, x_min
        size = (x_max - x_min, y_max - y_min, top_m - bottom_m)
    centre = (centre_x, 0.0 if size is None else (profile.footprint_m[2]
                                                  + profile.footprint_m[3]) / 2.0,
              (bottom_m + top_m) / 2.0)
    for element in [visual for visual in base.findall('visual')
                    if visual.get('name') != MAST_VISUAL] + base.findall('collision'):
        geometry = _find(element, 'geometry', 'body geometry')
        for shape in list(geometry):
            geometry.remove(shape)
        if size is None:
            ET.SubElement(geometry, 'cylinder', radius=_numbers((profile.body_radius_m,)),
                          length=_numbers((top_m - bottom_m,)))
        else:
            ET.SubElement(geometry, 'box', size=_numbers(size))
        _set_xyz(element, centre)
    mass = profile.mass_kg
    height = top_m - bottom_m
    if size is None:
        side_moment = mass * (3.0 * profile.body_radius_m ** 2 + height ** 2) / 12.0
        ixx = iyy = side_moment
        izz = mass * profile.body_radius_m ** 2 / 2.0
    else:
        ixx = mass * (size[1] ** 2 + height ** 2) / 12.0
        iyy = mass * (size[0] ** 2 + height ** 2) / 12.0
        izz = mass * (size[0] ** 2 + size[1] ** 2) / 12.0
    inertial = _find(base, 'inertial', 'base_link inertial')
    com_x = centre_x + COM_AHEAD_M
    _set_xyz(inertial, (com_x, centre[1], centre[2]))
    _find(inertial, 'mass', 'base_link mass').set('value', _numbers((mass,)))
    inertia = _find(inertial, 'inertia', 'base_link inertia')
    for key, value in (('ixx', ixx), ('iyy', iyy), ('izz', izz)):
        inertia.set(key, _numbers((value,)))
    for side, sign in (('left', 1.0), ('right', -1.0)):
        joint = _find(robot, "joint[@name='%s_wheel_joint']" % side, '%s wheel joint' % side)
        _set_xyz(joint, (0.0, sign * profile.wheel_separation_m / 2.0, profile.wheel_radius_m))
        wheel = _find(robot, "link[@name='%s_wheel']" % side, '%s wheel' % side)
        for shape in wheel.iter():
            if shape.tag in ('cylinder', 'sphere'):
                shape.set('radius', _numbers((profile.wheel_radius_m,)))
    front_rests = com_x >= 0.0
    for caster, x_m, rests in (('front_caster', front_x - CASTER_INSET_M, front_rests),
                               ('rear_caster', back_x + CASTER_INSET_M, not front_rests)):
        joint = _find(robot, "joint[@name='%s_joint']" % caster, '%s joint' % caster)
        _set_xyz(joint, (x_m, 0.0, CASTER_RESTING_Z_M if rests else CASTER_FLOATING_Z_M))
    mast = base.find("visual[@name='%s']" % MAST_VISUAL)
    if mast is not None:
        length_m = float(_find(mast, 'geometry/cylinder', 'camera_mast cylinder').get('length'))
        _set_xyz(mast, (profile.camera.forward_m - MAST_BEHIND_CAMERA_M, 0.0,
                        top_m + length_m / 2.0))


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
               link_prefix: str = '', profile: Optional[RobotProfile] = None) -> str:
    """The URDF text ``template`` (the robot at any camera mount) with ``profile``'s body
    (:func:`apply_body`; None: the template's) and ``mount`` applied and its links renamed (:func:`rename_links`: ``link_names`` such as {'base_link':
    'robot1/base_link'}, ``link_prefix`` for the links not in it).

    Comments and every other element are kept; raises ValueError when the template has no
    camera joints.
    """
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    robot = ET.fromstring(template, parser=parser)
    if profile is not None:
        apply_body(robot, profile)
    apply_mount(robot, mount)
    if link_names or link_prefix:
        rename_links(robot, link_names or {}, link_prefix)
    start = re.search(r'<robot[\s>]', template)
    head = template[:start.start()] if start else '<?xml version="1.0"?>\n'
    return head + ET.tostring(robot, encoding='unicode') + '\n'

