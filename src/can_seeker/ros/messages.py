"""Message builders: every ROS message the nodes publish is made here from plain values (numbers,
numpy arrays, the pure modules' results), so the nodes only wire topics and the builders are
tested without a master."""
import math
import struct

import numpy as np
from geometry_msgs.msg import PoseStamped, TransformStamped, Twist, TwistStamped
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from sensor_msgs.msg import CameraInfo, Image, LaserScan
from visualization_msgs.msg import Marker, MarkerArray

from can_seeker.msg import CanDetection
from can_seeker.camera_mount import OPTICAL_IN_CAMERA_LINK_XYZW

IMAGE_BUFF_SIZE = 2 ** 24
"""Image subscriber socket buffer (bytes): with queue_size=1 it keeps only the newest frame."""

STATE_TEXT_HEIGHT_M = 0.5
"""The controller state's text floats this high above base_link (m)."""
STATE_TEXT_SIZE_M = 0.12
CAN_RGBA = (0.9, 0.1, 0.1, 0.8)
STATE_RGBA = (1.0, 1.0, 1.0, 1.0)


class ArrayImage(Image):
    """A sensor_msgs/Image whose ``data`` is a C-contiguous uint8 numpy array, written to the
    wire straight from the array's memory: Image.serialize wants bytes and packs them again,
    two copies of every image published (0.07 ms per 640x480 bgr8 image)."""

    def serialize(self, buff):
        """The sensor_msgs/Image wire format (header, height, width, encoding, is_bigendian,
        step, data), as Image.serialize writes it."""
        header = self.header
        frame_id = header.frame_id.encode('utf-8')
        encoding = self.encoding.encode('utf-8')
        buff.write(struct.pack('<4I', header.seq, header.stamp.secs, header.stamp.nsecs,
                               len(frame_id)))
        buff.write(frame_id)
        buff.write(struct.pack('<3I', self.height, self.width, len(encoding)))
        buff.write(encoding)
        buff.write(struct.pack('<BII', self.is_bigendian, self.step, self.data.nbytes))
        buff.write(self.data.data)


def image_msg(header, array, encoding):
    """sensor_msgs/Image of a uint8 array (mono8: 2-D, bgr8: 3-D) that stays unchanged until
    the message is published (publish serialises it at once); contiguous arrays are not
    copied."""
    array = np.ascontiguousarray(array)
    height, width = array.shape[:2]
    return ArrayImage(header=header, height=height, width=width, encoding=encoding,
                      is_bigendian=0, step=array.strides[0], data=array)


def detection_msg(header, report) -> CanDetection:
    """can_seeker/CanDetection of a :class:`can_seeker.vision.report.CanReport`, with the
    image's header."""
    detection = CanDetection(header=header, found=report.found,
                             centroid_x=report.centroid_x, centroid_y=report.centroid_y,
                             area=report.area, image_width=report.image_width,
                             image_height=report.image_height, bearing=report.bearing_rad,
                             range=report.range_m, confidence=report.confidence)
    detection.bbox.x_offset, detection.bbox.y_offset, detection.bbox.width, \
        detection.bbox.height = report.bbox
    return detection


def laser_scan(geometry, ranges, stamp, frame_id) -> LaserScan:
    """sensor_msgs/LaserScan of ``ranges`` (m) over a scan ``geometry`` (angle_min, angle_max,
    angle_increment, range_min, range_max)."""
    scan = LaserScan(angle_min=geometry.angle_min, angle_max=geometry.angle_max,
                     angle_increment=geometry.angle_increment, time_increment=0.0,
                     scan_time=0.0, range_min=geometry.range_min,
                     range_max=geometry.range_max, ranges=list(ranges))
    scan.header.stamp = stamp
    scan.header.frame_id = frame_id
    return scan


def twist(linear, angular) -> Twist:
    """A planar Twist (m/s, rad/s)."""
    message = Twist()
    message.linear.x = linear
    message.angular.z = angular
    return message


def twist_stamped(message: Twist, stamp) -> TwistStamped:
    """``message`` stamped with the time it is for."""
    stamped = TwistStamped(twist=message)
    stamped.header.stamp = stamp
    return stamped


def transform_stamped(stamp, parent, child, translation, rotation_xyzw) -> TransformStamped:
    """The TF of ``child`` in ``parent``."""
    transform = TransformStamped()
    transform.header.stamp = stamp
    transform.header.frame_id = parent
    transform.child_frame_id = child
    (transform.transform.translation.x, transform.transform.translation.y,
     transform.transform.translation.z) = translation
    (transform.transform.rotation.x, transform.transform.rotation.y,
     transform.transform.rotation.z, transform.transform.rotation.w) = rotation_xyzw
    return transform


def mount_transforms(stamp, mount, base_frame='base_link', camera_frame='camera_link',
                     optical_frame='camera_optical_frame'):
    """The camera mount's TF (a :class:`can_seeker.camera_mount.CameraMount`): base_frame ->
    camera_frame (REP-103) -> optical_frame (z forward, x right, y down)."""
    return [transform_stamped(stamp, base_frame, camera_frame, mount.translation_m,
                              mount.rotation_xyzw),
            transform_stamped(stamp, camera_frame, optical_frame, (0.0, 0.0, 0.0),
                              OPTICAL_IN_CAMERA_LINK_XYZW)]


def camera_info(intrinsics, distortion, frame_id) -> CameraInfo:
    """sensor_msgs/CameraInfo (plumb_bob) of pinhole ``intrinsics`` in optical frame
    ``frame_id``."""
    info = CameraInfo()
    info.header.frame_id = frame_id
    info.width = intrinsics.width
    info.height = intrinsics.height
    info.distortion_model = 'plumb_bob'
    info.D = list(distortion)
    info.K = intrinsics.K
    info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    info.P = intrinsics.P
    return info


def odometry(stamp, frame_id, child_frame_id, position, orientation_xyzw, linear,
             angular) -> Odometry:
    """nav_msgs/Odometry of ``child_frame_id`` in ``frame_id``."""
    odom = Odometry()
    odom.header.stamp = stamp
    odom.header.frame_id = frame_id
    odom.child_frame_id = child_frame_id
    pose = odom.pose.pose
    pose.position.x, pose.position.y, pose.position.z = position
    (pose.orientation.x, pose.orientation.y, pose.orientation.z,
     pose.orientation.w) = orientation_xyzw
    twist_ = odom.twist.twist
    twist_.linear.x, twist_.linear.y, twist_.linear.z = linear
    twist_.angular.x, twist_.angular.y, twist_.angular.z = angular
    return odom


def occupancy_grid(values, resolution_m, origin_xy, frame_id, stamp) -> OccupancyGrid:
    """nav_msgs/OccupancyGrid of ``values`` (int8 rows along y, columns along x, row 0 at the
    origin cell: 100 occupied, 0 free, -1 unknown), cells ``resolution_m`` wide, the origin
    cell's corner at ``origin_xy`` in ``frame_id``."""
    values = np.asarray(values, np.int8)
    message = OccupancyGrid()
    message.header.stamp = stamp
    message.header.frame_id = frame_id
    message.info.map_load_time = stamp
    message.info.resolution = float(resolution_m)
    message.info.height, message.info.width = values.shape
    message.info.origin.position.x, message.info.origin.position.y = (float(origin_xy[0]),
                                                                      float(origin_xy[1]))
    message.info.origin.orientation.w = 1.0
    message.data = values.reshape(-1).tolist()
    return message


def path_msg(path_xy, frame_id, stamp) -> Path:
    """nav_msgs/Path through the points ``path_xy`` (N x 2, m, in ``frame_id``; None: an empty
    path), each pose heading along the path."""
    message = Path()
    message.header.stamp = stamp
    message.header.frame_id = frame_id
    points = [] if path_xy is None else np.asarray(path_xy, float).reshape(-1, 2)
    for index, (x_m, y_m) in enumerate(points):
        pose = PoseStamped()
        pose.header = message.header
        pose.pose.position.x, pose.pose.position.y = float(x_m), float(y_m)
        yaw = 0.0
        if len(points) > 1:
            start, end = ((points[index], points[index + 1]) if index + 1 < len(points)
                          else (points[index - 1], points[index]))
            yaw = math.atan2(end[1] - start[1], end[0] - start[0])
        pose.pose.orientation.z, pose.pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
        message.poses.append(pose)
    return message


def _marker(namespace, kind, frame_id, stamp, rgba) -> Marker:
    marker = Marker()
    marker.header.stamp = stamp
    marker.header.frame_id = frame_id
    marker.ns = namespace
    marker.id = 0
    marker.type = kind
    marker.pose.orientation.w = 1.0
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = rgba
    return marker


def controller_markers(can_xy, can_radius_m, can_height_m, robot_xy, state, frame_id,
                       stamp) -> MarkerArray:
    """visualization_msgs/MarkerArray of the controller in ``frame_id``: the can estimate
    ``can_xy`` as a CYLINDER (ns "can"; deleted while there is none) and the ``state`` as a
    TEXT_VIEW_FACING above ``robot_xy`` (ns "state"; deleted while the pose is unknown)."""
    can = _marker('can', Marker.CYLINDER, frame_id, stamp, CAN_RGBA)
    if can_xy is None:
        can.action = Marker.DELETE
    else:
        can.action = Marker.ADD
        can.pose.position.x, can.pose.position.y = float(can_xy[0]), float(can_xy[1])
        can.pose.position.z = can_height_m / 2.0
        can.scale.x = can.scale.y = 2.0 * can_radius_m
        can.scale.z = can_height_m
    text = _marker('state', Marker.TEXT_VIEW_FACING, frame_id, stamp, STATE_RGBA)
    text.text = state
    text.scale.z = STATE_TEXT_SIZE_M
    if robot_xy is None:
        text.action = Marker.DELETE
    else:
        text.action = Marker.ADD
        text.pose.position.x, text.pose.position.y = float(robot_xy[0]), float(robot_xy[1])
        text.pose.position.z = STATE_TEXT_HEIGHT_M
    return MarkerArray(markers=[can, text])
