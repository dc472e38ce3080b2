"""Ground truth of the recorded simulator bag: where the can really was in every image, from
the true pose (/sim/base_pose_ground_truth), /sim/can_pose, /tf_static and camera_info recorded
with it."""
import bisect
import math
import warnings

import numpy as np
import rosbag
import rospy
import tf2_ros

from can_seeker.camera_geometry import camera_pose_from_transform, intrinsics_from_k
from can_seeker.can_size import CAN_COLOUR_BOTTOM_M

TRUE_POSE_TOPIC = '/sim/base_pose_ground_truth'
"""The true base pose; bags recorded before it existed have /odom, then the true pose too."""
CAN_RADIUS_M = 0.033
CAN_HEIGHT_M = 0.122
CENTROID_TOLERANCE_PX = 3.0
BEARING_TOLERANCE_RAD = 0.01


def range_tolerance_m(true_range_m):
    return max(0.01, 0.02 * true_range_m)


class GroundTruth:
    """Where the can was relative to the camera at any stamp of the bag."""

    def __init__(self, path):
        tf_core = tf2_ros.BufferCore()
        poses = {'/odom': [], TRUE_POSE_TOPIC: []}
        self.can, self.image_stamps, info = [], [], None
        with rosbag.Bag(path) as bag:
            for topic, msg, _ in bag.read_messages(
                    topics=['/tf_static', '/odom', TRUE_POSE_TOPIC, '/sim/can_pose',
                            '/camera/camera_info', '/camera/image_raw']):
                if topic == '/tf_static':
                    with warnings.catch_warnings():
                        # Bag messages are generated classes; tf2 warns, then copes.
                        warnings.simplefilter('ignore', UserWarning)
                        for transform in msg.transforms:
                            tf_core.set_transform_static(transform, 'bag')
                elif topic in poses:
                    pose = msg.pose.pose
                    yaw = 2.0 * math.atan2(pose.orientation.z, pose.orientation.w)
                    poses[topic].append((msg.header.stamp.to_sec(), pose.position.x,
                                         pose.position.y, yaw))
                elif topic == '/sim/can_pose':
                    self.can.append((msg.header.stamp.to_sec(), msg.pose.position.x,
                                     msg.pose.position.y))
                elif topic == '/camera/camera_info' and info is None:
                    info = msg
                elif topic == '/camera/image_raw':
                    self.image_stamps.append(msg.header.stamp.to_sec())
        self.odom = poses[TRUE_POSE_TOPIC] or poses['/odom']
        self.intrinsics = intrinsics_from_k(info.width, info.height, info.K)
        transform = tf_core.lookup_transform_core('base_link', info.header.frame_id,
                                                  rospy.Time(0)).transform
        self.camera = camera_pose_from_transform(
            (transform.translation.x, transform.translation.y, transform.translation.z),
            (transform.rotation.x, transform.rotation.y, transform.rotation.z,
             transform.rotation.w))

    @staticmethod
    def _nearest(samples, stamp):
        index = bisect.bisect_left([sample[0] for sample in samples], stamp)
        candidates = [samples[i] for i in (index - 1, index) if 0 <= i < len(samples)]
        return min(candidates, key=lambda sample: abs(sample[0] - stamp))

    def can_in_base(self, stamp):
        """Can centre (x, y) in base_link (m) at ``stamp``."""
        _, robot_x, robot_y, yaw = self._nearest(self.odom, stamp)
        _, can_x, can_y = self._nearest(self.can, stamp)
        dx, dy = can_x - robot_x, can_y - robot_y
        return (math.cos(yaw) * dx + math.sin(yaw) * dy, -math.sin(yaw) * dx + math.cos(yaw) * dy)

    def project(self, point_base):
        """Pixel (u, v) of a base_link point, or None behind the camera."""
        offset = np.asarray(point_base) - np.asarray(self.camera.position)
        optical = self.camera.rotation.T @ offset
        if optical[2] <= 0.0:
            return None
        return (self.intrinsics.fx * optical[0] / optical[2] + self.intrinsics.cx,
                self.intrinsics.fy * optical[1] / optical[2] + self.intrinsics.cy)

    def plain_can_range(self, range_m, bearing_rad):
        """The floor range image_converter gives these bags' can, plain red down to the floor,
        whose true floor range is ``range_m`` at ``bearing_rad``: it takes the blob's lower
        edge for where the can's colour begins, CAN_COLOUR_BOTTOM_M above the floor, so it
        ranges the point of that edge's ray at that height, nearer along the camera's heading
        by the ratio of the heights below the camera (see
        camera_geometry.range_from_floor)."""
        height_m = self.camera.position[2]
        forward_m = (range_m + CAN_RADIUS_M) * math.cos(bearing_rad) - CAN_RADIUS_M
        forward_m *= (height_m - CAN_COLOUR_BOTTOM_M) / height_m
        return (forward_m + CAN_RADIUS_M) / math.cos(bearing_rad) - CAN_RADIUS_M

    def truth(self, stamp):
        """(visibility, centre pixel, range m, bearing rad) of the can at ``stamp``.

        visibility: 'inside' (the whole can projects into the image), 'outside' (none of it
        does), or 'partly'.
        """
        x, y = self.can_in_base(stamp)
        outline = [self.project((x + CAN_RADIUS_M * math.cos(angle),
                                 y + CAN_RADIUS_M * math.sin(angle), z))
                   for angle in np.linspace(0.0, 2.0 * math.pi, 24, endpoint=False)
                   for z in (0.0, CAN_HEIGHT_M)]
        inside = [point is not None and 1.0 <= point[0] < self.intrinsics.width - 1.0
                  and 1.0 <= point[1] < self.intrinsics.height - 1.0 for point in outline]
        visibility = 'inside' if all(inside) else 'outside' if not any(inside) else 'partly'
        forward, left = x - self.camera.position[0], y - self.camera.position[1]
        return (visibility, self.project((x, y, CAN_HEIGHT_M / 2.0)),
                math.hypot(forward, left) - CAN_RADIUS_M, math.atan2(left, forward))
