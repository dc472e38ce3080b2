"""Shared by the simulator rostest nodes: ground truth recording, velocity commands, services,
and the red blob of an image measured with plain numpy (independent of the vision module)."""
import math
import threading
import time

import numpy as np
import rospy
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool
from std_srvs.srv import Empty

from can_seeker.srv import PlaceCan

CAN_HEIGHT_M = 0.122
CAN_RADIUS_M = 0.033


def yaw_of(orientation):
    """Heading (rad) of a geometry_msgs/Quaternion."""
    return math.atan2(2.0 * (orientation.w * orientation.z + orientation.x * orientation.y),
                      1.0 - 2.0 * (orientation.y ** 2 + orientation.z ** 2))


def red_blob(image, red_channel):
    """(centroid (u, v), bbox (u_min, u_max, v_min, v_max), pixel count) of the red pixels."""
    red = image[:, :, red_channel].astype(int)
    green = image[:, :, 1].astype(int)
    blue = image[:, :, 2 - red_channel].astype(int)
    rows, columns = np.nonzero((red > 60) & (red > 2 * green) & (red > 2 * blue))
    if rows.size == 0:
        return None, None, 0
    return ((columns.mean(), rows.mean()),
            (columns.min(), columns.max(), rows.min(), rows.max()), rows.size)


class SimHarness:
    """Records the true pose (/sim/base_pose_ground_truth), /sim/can_pose and /sim/contact with their stamps; drives via /cmd_vel."""

    def __init__(self):
        self.lock = threading.Lock()
        self.odom = []
        self.contacts = []
        self.can_pose = None
        self.cmd_pub = rospy.Publisher('/cmd_vel', Twist, queue_size=10)
        rospy.Subscriber('/sim/base_pose_ground_truth', Odometry, self.on_odom)
        rospy.Subscriber('/sim/can_pose', PoseStamped, self.on_can_pose)
        rospy.Subscriber('/sim/contact', Bool, self.on_contact)
        rospy.wait_for_service('/sim/reset', timeout=30.0)
        rospy.wait_for_service('/sim/place_can', timeout=30.0)
        self.reset_service = rospy.ServiceProxy('/sim/reset', Empty)
        self.place_can_service = rospy.ServiceProxy('/sim/place_can', PlaceCan)
        self.wait_until(lambda: self.odom and self.can_pose is not None
                        and self.cmd_pub.get_num_connections() > 0, 30.0)

    def on_odom(self, message):
        pose, twist = message.pose.pose, message.twist.twist
        with self.lock:
            self.odom.append((message.header.stamp.to_sec(), pose.position.x, pose.position.y,
                              yaw_of(pose.orientation), twist.linear.x, twist.angular.z))

    def on_can_pose(self, message):
        self.can_pose = message

    def on_contact(self, message):
        with self.lock:
            self.contacts.append((rospy.get_time(), message.data))

    @staticmethod
    def wait_until(predicate, timeout_wall_s):
        """Poll ``predicate`` until it holds; raise AssertionError after ``timeout_wall_s``."""
        deadline = time.monotonic() + timeout_wall_s
        while not predicate():
            if time.monotonic() > deadline:
                raise AssertionError('timed out waiting for the simulator')
            time.sleep(0.01)

    def pose(self):
        """(x m, y m, yaw rad) of the latest /odom."""
        with self.lock:
            return self.odom[-1][1:4]

    def odom_between(self, start_s, end_s):
        """(stamp, x, y, yaw, v, w) of /odom messages stamped in [start_s, end_s] (sim time)."""
        with self.lock:
            return [sample for sample in self.odom if start_s <= sample[0] <= end_s]

    def contacts_since(self, start_s):
        """/sim/contact values received after ``start_s`` (sim time)."""
        with self.lock:
            return [touching for stamp, touching in self.contacts if stamp >= start_s]

    def settle(self, duration_s):
        """Wait ``duration_s`` of sim time and until ground truth and /sim/can_pose (each a
        connection of its own) have caught up with the clock."""
        rospy.sleep(duration_s)
        now_s = rospy.get_time()
        self.wait_until(lambda: self.odom[-1][0] >= now_s - 0.05
                        and self.can_pose.header.stamp.to_sec() >= now_s - 0.05, 10.0)

    def reset(self):
        """Robot back at the origin at rest."""
        self.cmd_pub.publish(Twist())
        self.reset_service()
        self.settle(0.3)

    def place_can(self, x_m, y_m):
        """Put the can at (x, y) in odom; fails the test if refused."""
        response = self.place_can_service(x_m, y_m)
        assert response.success, response.message
        self.settle(0.1)

    def drive(self, linear_mps, angular_radps, duration_s, rate_hz=20.0):
        """Publish the twist at ``rate_hz`` for ``duration_s`` of sim time; returns the sim time
        of the last publication. The caller decides whether to publish a stop afterwards."""
        twist = Twist()
        twist.linear.x, twist.angular.z = linear_mps, angular_radps
        end_s = rospy.get_time() + duration_s
        rate = rospy.Rate(rate_hz)
        last_s = rospy.get_time()
        while rospy.get_time() < end_s:
            self.cmd_pub.publish(twist)
            last_s = rospy.get_time()
            rate.sleep()
        return last_s

    def stop(self):
        """Publish a zero twist."""
        self.cmd_pub.publish(Twist())
