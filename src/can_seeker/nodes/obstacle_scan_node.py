"""obstacle_scan: camera images -> a planar LaserScan of the obstacles standing on the floor.

Subscribes ``image`` (sensor_msgs/Image; with ``~image_transport`` compressed
``image/compressed``, sensor_msgs/CompressedImage, jpeg or png; queue_size=1, large
buff_size: always the newest frame) and ``camera_info``; publishes ``camera_scan`` (sensor_msgs/LaserScan in ``~scan_frame``, stamped
with the image's stamp) and, only while subscribed, ``~annotated`` (bgr8) and ``~obstacles``
(mono8), and /diagnostics (the rates and ages of the images and camera_info, whether the
recent frames gave a scan and if not why). The camera pose comes from TF (``~scan_frame`` <-
image frame, which must be an optical frame; :mod:`can_seeker.ros.camera_pose`): until TF has
it there is no scan, and an error says which transform is missing; camera_info's D is
undone on the pixels the scan's geometry uses unless ``~image_rectified``. ``~reset``
(std_srvs/Empty) forgets the learned floor model, so a new trial does not inherit the last
one's, and skips the frames stamped at or before the reset that are still on their way (they
show the world before it; which of them arrive after the reset depends on the machine's load).
"""
import math
import threading
import time

import rospy
from sensor_msgs.msg import CameraInfo, Image, LaserScan
from std_srvs.srv import Empty, EmptyResponse

from can_seeker.allocator import reuse_freed_memory
from can_seeker.camera_geometry import intrinsics_from_camera_info
from can_seeker.health import ERROR, OK, Outcomes
from can_seeker.opencv_threads import use_one_opencv_thread
from can_seeker.params import read_params
from can_seeker.ros.camera_pose import CameraPoseSource, missing_transform
from can_seeker.ros.sensor_tf import SensorTf
from can_seeker.ros.diagnostics import image_diagnostics
from can_seeker.ros.messages import image_msg, laser_scan
from can_seeker.throttle import KindThrottle
from can_seeker.vision.camera_scan import PARAMS, CameraScanner, draw_obstacles
from can_seeker.vision.floor import FloorSettings
from can_seeker.ros.image_input import image_decoder, image_topic, subscribe_images
from can_seeker.vision.image_decode import DecodedImage, ImageDecodeError, NoColourError

ERROR_PERIOD_S = 5.0


class ObstacleScanNode:
    def __init__(self):
        self.config = read_params(PARAMS, rospy.get_param, rospy.logwarn)
        self.scanner = CameraScanner(FloorSettings.from_values(self.config),
                                     self.config.max_range, self.config.exclude_can,
                                     robot_radius_m=self.config.robot_radius,
                                     robot_height_m=self.config.robot_height)
        self.intrinsics = None
        self.decode_errors = KindThrottle(ERROR_PERIOD_S)
        self.scanner_lock = threading.Lock()
        self.reset_s = -math.inf
        self.tf = SensorTf(warn=lambda message: rospy.logwarn('obstacle_scan: %s' % message))
        self.camera_poses = CameraPoseSource.from_tf(
            self.tf, self.config.scan_frame, 'obstacle_scan', require_optical=True,
            without='no scan')
        self.scan_pub = rospy.Publisher('camera_scan', LaserScan, queue_size=1)
        self.annotated_pub = rospy.Publisher('~annotated', Image, queue_size=1)
        self.obstacles_pub = rospy.Publisher('~obstacles', Image, queue_size=1)
        self.outcomes = Outcomes()
        self.diagnostics, self.image_monitor, self.info_monitor = image_diagnostics(
            self.outcomes, image_topic(self.config.image_transport),
            rospy.resolve_name('camera_info'))
        rospy.Service('~reset', Empty, self.on_reset)
        rospy.Subscriber('camera_info', CameraInfo, self.on_camera_info, queue_size=1)
        self.decode = image_decoder(self.config.image_transport)
        subscribe_images('obstacle_scan', self.config.image_transport, self.on_image)
        self.diagnostics.start()


    def on_reset(self, _request):
        with self.scanner_lock:
            self.reset_s = rospy.get_time()
            self.scanner.floor.reset()
        return EmptyResponse()

    def on_camera_info(self, msg):
        try:
            self.intrinsics = intrinsics_from_camera_info(
                msg.width, msg.height, msg.K, msg.D, msg.P, msg.distortion_model,
                self.config.image_rectified)
        except ValueError as error:
            self.info_monitor.received(rospy.get_time(), msg.header.stamp.to_sec(), str(error))
            rospy.logerr_throttle(ERROR_PERIOD_S, 'obstacle_scan: ignoring camera_info: %s'
                                  % error)
            return
        self.info_monitor.received(rospy.get_time(), msg.header.stamp.to_sec())

    def camera_intrinsics(self, msg):
        intrinsics = self.intrinsics
        if intrinsics is None:
            rospy.logwarn_throttle(ERROR_PERIOD_S, 'obstacle_scan: no camera_info yet: no scan')
        elif (intrinsics.width, intrinsics.height) != (msg.width, msg.height):
            rospy.logerr_throttle(ERROR_PERIOD_S, 'obstacle_scan: camera_info is %dx%d but the '
                                  'image is %dx%d: no scan' % (intrinsics.width, intrinsics.height,
                                                               msg.width, msg.height))
            return None
        return intrinsics

    def on_image(self, msg):
        self.image_monitor.received(rospy.get_time(), msg.header.stamp.to_sec())
        try:
            image = DecodedImage(msg.header, self.decode(msg))
        except NoColourError as error:
            rospy.logwarn_once('obstacle_scan: no scan from grey images: %s' % error)
            self.outcomes.add('no scan: grey images', ERROR)
            return
        except ImageDecodeError as error:
            self.outcomes.add('skipped: %s' % error.kind, ERROR)
            self.log_decode_error(error)
            return
        # Subscribers come and go while a frame is processed: decide once what to build.
        want_obstacles = self.obstacles_pub.get_num_connections() > 0
        want_annotated = self.annotated_pub.get_num_connections() > 0
        bgr = image.bgr
        intrinsics = self.camera_intrinsics(image)
        pose = (self.camera_poses.pose(msg.header.frame_id, rospy.get_time()) if intrinsics
                else None)
        with self.scanner_lock:
            if msg.header.stamp.to_sec() <= self.reset_s:
                self.outcomes.add('skipped: taken before the last reset', OK)
                return
            result = self.scanner.scan(bgr, pose, intrinsics)
        if result.ranges is not None:
            self.publish_scan(msg.header.stamp, result.ranges)
            self.outcomes.add('scan', OK)
        elif intrinsics is None:
            self.outcomes.add('no scan: no usable camera_info', ERROR)
        elif pose is None and msg.header.frame_id.lstrip('/') in self.camera_poses.problems:
            self.outcomes.add('no scan: the image frame is not an optical frame', ERROR)
        elif pose is None:
            self.outcomes.add('no scan: %s' % missing_transform(self.config.scan_frame,
                                                                msg.header.frame_id), ERROR)
        else:
            self.outcomes.add('no scan: no floor in view within ~max_range', ERROR)
            rospy.logwarn_throttle(ERROR_PERIOD_S, 'obstacle_scan: the camera sees no floor '
                                   'within ~max_range: no scan')
        if want_obstacles:
            self.obstacles_pub.publish(image_msg(msg.header, result.obstacles, 'mono8'))
        if want_annotated:
            annotated = draw_obstacles(bgr, result, self.scanner.floor.reference_corners)
            self.annotated_pub.publish(image_msg(msg.header, annotated, 'bgr8'))

    def log_decode_error(self, error):
        """One ERROR per kind of fault every ERROR_PERIOD_S, saying how many were held back."""
        allowed, held_back = self.decode_errors.allow(error.kind, time.monotonic())
        if allowed:
            rospy.logerr('obstacle_scan: skipping frame: %s%s' % (
                error, ' (%d more %s faults since the last report)' % (held_back, error.kind)
                if held_back else ''))

    def publish_scan(self, stamp, ranges):
        self.scan_pub.publish(laser_scan(self.scanner.geometry, ranges.tolist(), stamp,
                                         self.config.scan_frame))


def main():
    reuse_freed_memory()
    use_one_opencv_thread()
    rospy.init_node('obstacle_scan')
    ObstacleScanNode()
    rospy.spin()
