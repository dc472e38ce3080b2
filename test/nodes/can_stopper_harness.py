"""Shared by the can_stopper rostest nodes: feed CanDetection messages, record /cmd_vel and the
stamps of cmd_vel_stamped; without a simulator, publish the camera's TF."""
import threading
import time

import rospy
import tf2_ros
from geometry_msgs.msg import Twist, TwistStamped
from std_msgs.msg import String

from can_seeker.camera_mount import CameraMount
from can_seeker.msg import CanDetection
from can_seeker.ros.messages import mount_transforms

FRAME = 'camera_optical_frame'
MOUNT = CameraMount(0.25, 25.0)
"""The camera mount broadcast_static_tf publishes (the simulated robot's)."""


def broadcast_static_tf(*transforms):
    """The camera's mount (MOUNT: base_link -> camera_link -> FRAME) and ``transforms`` on
    /tf_static, in one latched message (a node's broadcasters share it): can_stopper places
    a detection only through TF. Keep the returned broadcaster."""
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    broadcaster.sendTransform(mount_transforms(rospy.Time(0), MOUNT, optical_frame=FRAME)
                              + list(transforms))
    return broadcaster


def detection(range_m, bearing_rad, confidence=1.0):
    """A found can at ``range_m`` (camera to near surface) and ``bearing_rad``, that the
    detector is ``confidence`` sure is the can."""
    message = CanDetection()
    message.header.stamp = rospy.Time.now()
    message.header.frame_id = FRAME
    message.found = True
    message.range = range_m
    message.bearing = bearing_rad
    message.confidence = confidence
    message.image_width, message.image_height = 320, 240
    return message


class Harness:
    """Publishes detections and records every /cmd_vel with its wall-clock arrival time."""

    def __init__(self):
        self.lock = threading.Lock()
        self.commands = []
        self.stamped = []
        self.state = None
        self.detection_pub = rospy.Publisher('/image_converter/detection', CanDetection,
                                             queue_size=1)
        rospy.Subscriber('/cmd_vel', Twist, self.on_cmd_vel)
        rospy.Subscriber('/cmd_vel_stamped', TwistStamped, self.on_cmd_vel_stamped)
        rospy.Subscriber('/can_stopper/state', String, self.on_state)

    def on_cmd_vel(self, message):
        with self.lock:
            self.commands.append((time.monotonic(), message.linear.x, message.angular.z))

    def on_cmd_vel_stamped(self, message):
        with self.lock:
            self.stamped.append((message.header.stamp.to_sec(), message.twist.linear.x,
                                 message.twist.angular.z))

    def stamped_since(self, stamp_s):
        """(stamp s, linear m/s, angular rad/s) of the stamped commands for times after
        ``stamp_s`` (ROS time): when each was decided, whenever it arrived."""
        with self.lock:
            return [command for command in self.stamped if command[0] > stamp_s]

    def on_state(self, message):
        self.state = message.data

    def commands_since(self, start):
        """(arrival s, linear m/s, angular rad/s) of the commands received after ``start``."""
        with self.lock:
            return [command for command in self.commands if command[0] > start]

    def wait_for_connections(self, timeout_s=10.0):
        """Wait until can_stopper subscribes to the detections and publishes commands."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if self.detection_pub.get_num_connections() > 0 and self.commands_since(0.0):
                return True
            time.sleep(0.05)
        return False

    def feed(self, range_m, bearing_rad, duration_s, rate_hz=15.0, confidence=1.0):
        """Publish the same detection for ``duration_s``; return the stamp (s, ROS time) of the
        last one sent."""
        end = time.monotonic() + duration_s
        last_stamp_s = None
        while time.monotonic() < end:
            message = detection(range_m, bearing_rad, confidence)
            self.detection_pub.publish(message)
            last_stamp_s = message.header.stamp.to_sec()
            time.sleep(1.0 / rate_hz)
        return last_stamp_s
