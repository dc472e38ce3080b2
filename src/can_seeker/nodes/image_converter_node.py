"""image_converter: finds the red can in camera images and publishes a CanDetection per frame.

Subscribes ``image`` (sensor_msgs/Image; with ``~image_transport`` compressed
``image/compressed``, sensor_msgs/CompressedImage, jpeg or png; queue_size=1 and a large
buff_size: always the newest frame) and ``camera_info``; publishes ``~detection`` and, only while someone subscribes, ``~annotated``
(bgr8), ``~mask`` and ``~edges`` (mono8), and /diagnostics (the rates and ages of the
images and camera_info, what became of the recent frames). Thresholds are tunable with
dynamic_reconfigure.
The camera pose for range and bearing comes from TF (``~base_frame`` <- image frame, which
must be an optical frame; :mod:`can_seeker.ros.camera_pose`): until TF has it, detections
have NaN range and bearing, and an error says which transform is missing; camera_info's D is
undone on the pixels the geometry uses unless ``~image_rectified``.
"""
import time

import numpy as np
import rospy
from dynamic_reconfigure.server import Server
from sensor_msgs.msg import CameraInfo, Image

from can_seeker.allocator import reuse_freed_memory
from can_seeker.camera_geometry import intrinsics_from_camera_info
from can_seeker.cfg import ImageConverterConfig
from can_seeker.gui.display_check import OPENCV_WINDOW_PROBE, display_problem
from can_seeker.gui.windows import ImageWindows
from can_seeker.health import ERROR, OK, WARN, Outcomes
from can_seeker.msg import CanDetection
from can_seeker.opencv_threads import use_one_opencv_thread
from can_seeker.params import read_params
from can_seeker.ros.camera_pose import CameraPoseSource, missing_transform
from can_seeker.ros.sensor_tf import SensorTf
from can_seeker.ros.diagnostics import image_diagnostics
from can_seeker.ros.messages import detection_msg, image_msg
from can_seeker.vision.report import PARAMS, WINDOW_WIDTH_PX, CanModel, can_report
from can_seeker.ros.image_input import image_decoder, image_topic, subscribe_images
from can_seeker.vision.image_decode import DecodedImage, ImageDecodeError, NoColourError
from can_seeker.throttle import KindThrottle
from can_seeker.vision.detector import (DETECTOR_PARAMS, DetectorSettings, RedCanDetector,
                                        draw_annotation)

ERROR_PERIOD_S = 5.0


def frame_outcome(found, range_m, intrinsics, pose, frame_problem=None, missing_pose=''):
    """(outcome, level) of a processed frame for the diagnostics; ``missing_pose`` names the
    transform TF lacks when ``pose`` is None for want of it."""
    if not found:
        return 'no red object', OK
    if pose is None and frame_problem:
        return 'red object, no range: the image frame is not an optical frame', ERROR
    if intrinsics is None:
        return 'red object, no range: no usable camera_info', WARN
    if pose is None:
        return 'red object, no range: %s' % (missing_pose or 'camera pose unknown'), ERROR
    if np.isfinite(range_m):
        return 'red object with a range', OK
    return 'red object without a range', OK


def warn_unless_remapped(*names):
    """Warn like opencv_apps when an input topic still has its generic name."""
    generic = [name for name in names
               if rospy.resolve_name(name) == rospy.get_namespace() + name]
    if generic:
        rospy.logwarn("image_converter: topic %s not been remapped (listening on %s). Typical "
                      "command-line usage:\n\t$ rosrun can_seeker image_converter "
                      "image:=/camera/image_raw camera_info:=/camera/camera_info _show:=true"
                      % (' and '.join("'%s'" % name for name in generic)
                         + (' have' if len(generic) > 1 else ' has'),
                         ', '.join(rospy.resolve_name(name) for name in generic)))


class ImageConverterNode:
    def __init__(self):
        self.config = read_params(PARAMS, rospy.get_param, rospy.logwarn)
        for spec in DETECTOR_PARAMS:
            rospy.set_param('~' + spec.name, getattr(self.config, spec.name))
        self.detector = RedCanDetector(DetectorSettings.from_values(self.config))
        self.can_model = CanModel()
        self.intrinsics = None
        self.annotated_buffer = None
        self.tf = SensorTf(warn=lambda message: rospy.logwarn('image_converter: %s' % message))
        self.camera_poses = CameraPoseSource.from_tf(
            self.tf, self.config.base_frame, 'image_converter', require_optical=True,
            without='range and bearing are NaN')
        self.display = self._make_display(self.config.show)
        self.decode_errors = KindThrottle(ERROR_PERIOD_S)
        self.detection_pub = rospy.Publisher('~detection', CanDetection, queue_size=10)
        self.annotated_pub = rospy.Publisher('~annotated', Image, queue_size=1)
        self.mask_pub = rospy.Publisher('~mask', Image, queue_size=1)
        self.edges_pub = rospy.Publisher('~edges', Image, queue_size=1)
        self.reconfigure = Server(ImageConverterConfig, self.on_reconfigure)
        self.outcomes = Outcomes()
        self.diagnostics, self.image_monitor, self.info_monitor = image_diagnostics(
            self.outcomes, image_topic(self.config.image_transport),
            rospy.resolve_name('camera_info'))
        rospy.Subscriber('camera_info', CameraInfo, self.on_camera_info, queue_size=1)
        self.decode = image_decoder(self.config.image_transport)
        subscribe_images('image_converter', self.config.image_transport, self.on_image)
        self.diagnostics.start()


    def _make_display(self, show):
        """Image windows when ~show is true and a window can be opened; else None (headless)."""
        if not show:
            return None
        problem = display_problem(OPENCV_WINDOW_PROBE)
        if problem:
            rospy.logwarn('image_converter: ~show is true but %s: running headless' % problem)
            return None
        windows = ImageWindows(WINDOW_WIDTH_PX)
        rospy.on_shutdown(windows.close)
        return windows

    def on_reconfigure(self, config, _level):
        """Apply new thresholds atomically; invalid values fall back to the defaults."""
        values = read_params(DETECTOR_PARAMS, lambda name, default: config.get(name[1:], default),
                             rospy.logwarn)
        self.detector.settings = DetectorSettings.from_values(values)
        for spec in DETECTOR_PARAMS:
            config[spec.name] = getattr(values, spec.name)
        return config

    def on_camera_info(self, msg):
        try:
            self.intrinsics = intrinsics_from_camera_info(
                msg.width, msg.height, msg.K, msg.D, msg.P, msg.distortion_model,
                self.config.image_rectified)
        except ValueError as error:
            self.info_monitor.received(rospy.get_time(), msg.header.stamp.to_sec(), str(error))
            rospy.logerr_throttle(ERROR_PERIOD_S,
                                  'image_converter: ignoring camera_info: %s' % error)
            return
        self.info_monitor.received(rospy.get_time(), msg.header.stamp.to_sec())

    def camera_geometry(self, msg):
        """(pose, intrinsics) for this image; either is None when unknown."""
        intrinsics = self.intrinsics
        if intrinsics is None:
            rospy.logwarn_throttle(ERROR_PERIOD_S, 'image_converter: no camera_info yet: '
                                   'range and bearing are NaN')
        elif (intrinsics.width, intrinsics.height) != (msg.width, msg.height):
            rospy.logerr_throttle(ERROR_PERIOD_S, 'image_converter: camera_info is %dx%d but the '
                                  'image is %dx%d: range and bearing are NaN' % (
                                      intrinsics.width, intrinsics.height, msg.width, msg.height))
            intrinsics = None
        return self.camera_poses.pose(msg.header.frame_id, rospy.get_time()), intrinsics

    def on_image(self, msg):
        self.image_monitor.received(rospy.get_time(), msg.header.stamp.to_sec())
        try:
            image = DecodedImage(msg.header, self.decode(msg))
        except NoColourError as error:
            rospy.logwarn_once('image_converter: %s' % error)
            self.outcomes.add('grey images: no colour to find red in', ERROR)
            self.publish_detection(msg, can_report((), msg.width, msg.height, None, None,
                                                   self.can_model))
            return
        except ImageDecodeError as error:
            self.outcomes.add('skipped: %s' % error.kind, ERROR)
            self.log_decode_error(error)
            return
        # Subscribers come and go while a frame is processed: decide once what to build.
        want_mask = self.mask_pub.get_num_connections() > 0
        publish_edges = self.edges_pub.get_num_connections() > 0
        want_edges = self.display is not None or publish_edges
        want_annotated = self.annotated_pub.get_num_connections() > 0
        bgr = image.bgr
        result = self.detector.detect(bgr, want_edges)
        pose, intrinsics = self.camera_geometry(image) if result.found else (None, None)
        report = can_report(result.candidates, image.width, image.height, pose, intrinsics,
                            self.can_model)
        self.publish_detection(msg, report)
        self.outcomes.add(*frame_outcome(
            result.found, report.range_m, intrinsics, pose,
            self.camera_poses.problems.get(msg.header.frame_id.lstrip('/')),
            '' if pose is not None else missing_transform(self.config.base_frame,
                                                          msg.header.frame_id)))
        if want_mask:
            self.mask_pub.publish(image_msg(msg.header, result.mask, 'mono8'))
        if publish_edges:
            self.edges_pub.publish(image_msg(msg.header, result.edges, 'mono8'))
        if self.display is None and not want_annotated:
            return
        if self.annotated_buffer is None or self.annotated_buffer.shape != bgr.shape:
            self.annotated_buffer = np.empty(bgr.shape, np.uint8)
        # The display thread keeps what it is given: it gets an image of its own.
        annotated = draw_annotation(bgr, result, report.confidences, report.chosen,
                                    report.range_m,
                                    out=self.annotated_buffer if self.display is None else None)
        if want_annotated:
            self.annotated_pub.publish(image_msg(msg.header, annotated, 'bgr8'))
        if self.display is not None:
            self.display.offer({'origin': bgr.copy(), 'result': annotated,
                                'edges': result.edges.copy()})

    def log_decode_error(self, error):
        """One ERROR per kind of fault every ERROR_PERIOD_S, saying how many were held back."""
        allowed, held_back = self.decode_errors.allow(error.kind, time.monotonic())
        if allowed:
            rospy.logerr('image_converter: skipping frame: %s%s' % (
                error, ' (%d more %s faults since the last report)' % (held_back, error.kind)
                if held_back else ''))

    def publish_detection(self, image, report):
        self.detection_pub.publish(detection_msg(image.header, report))


def main():
    reuse_freed_memory()
    use_one_opencv_thread()
    rospy.init_node('image_converter')
    warn_unless_remapped('image', 'camera_info')
    ImageConverterNode()
    rospy.spin()

