"""bag_detect: the image_converter pipeline over a bag, offline (rosbag API, no master).

Writes one CSV row per image (stamp, found, centroid, area, bbox, range, bearing; by default
to ``bag_detect/<bag name>.csv`` in the workspace's or the ROS home, see
:mod:`can_seeker.output_paths`) and optionally an MP4 of the annotated images. With
``--scan-csv`` it also runs obstacle_scan's camera scan on every frame (one CSV row of
LaserScan ranges per frame, the obstacles drawn in the video), so the camera scan of a room can
be seen before the robot drives. Camera pose from the bag's TF (base frame <- image frame), by
the nodes' rule; for a bag recorded without the mount's TF, ``--camera-height`` (with
``--camera-pitch-deg`` and ``--camera-x``) gives the mount until the bag's TF has one. The image topic may
hold sensor_msgs/Image or sensor_msgs/CompressedImage (jpeg, png); the decoder follows the
topic's recorded type.
"""
import argparse
import csv
import math
import os
import sys
import warnings

import cv2
import rosbag
import rospy
import tf2_ros
from tqdm import tqdm

from can_seeker.camera_geometry import camera_pose_from_mount, intrinsics_from_camera_info
from can_seeker.camera_mount import CAMERA_FORWARD_M, CameraMount
from can_seeker.output_paths import default_output_dir
from can_seeker.vision import report
from can_seeker.vision.report import CanModel, can_report
from can_seeker.vision.image_decode import MESSAGE_DECODERS, ImageDecodeError, NoColourError
from can_seeker.ros.camera_pose import CameraPoseSource, missing_transform
from can_seeker.params import read_params
from can_seeker.vision.camera_scan import SCAN_PARAMS, CameraScanner, draw_obstacles
from can_seeker.vision.detector import DetectorSettings, RedCanDetector, draw_annotation
from can_seeker.vision.floor import FLOOR_PARAMS, FloorSettings

DEFAULT_IMAGE_TOPIC = '/camera/image_raw'
CAMERA_INFO_TYPE = 'sensor_msgs/CameraInfo'
TOOL_PARAMS = report.REPORT_PARAMS + FLOOR_PARAMS + SCAN_PARAMS
MOUNT_OPTIONS = ('a base frame other than base_link: --param base_frame=NAME --param '
                 'scan_frame=NAME; a bag without the mount\'s TF: --camera-height M')
"""What gives a frame whose transform the bag lacks a camera pose."""
CSV_COLUMNS = ('stamp', 'found', 'centroid_x', 'centroid_y', 'area', 'bbox_x', 'bbox_y',
               'bbox_width', 'bbox_height', 'range', 'bearing', 'range_method', 'confidence')


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('bag', help='input bag file')
    parser.add_argument('--csv', help='output CSV (default: the bag\'s name with .csv in %s)'
                        % default_output_dir('bag_detect'))
    parser.add_argument('--video', help='also write the annotated images to this MP4 file')
    parser.add_argument('--image-topic',
                        help='sensor_msgs/Image or CompressedImage topic (default: %s, else '
                             'the bag\'s only image topic)' % DEFAULT_IMAGE_TOPIC)
    parser.add_argument('--camera-info-topic',
                        help='sensor_msgs/CameraInfo topic (default: camera_info beside the '
                             'image topic, e.g. /raspicam_node/camera_info for '
                             '/raspicam_node/image/compressed, else the bag\'s only one)')
    parser.add_argument('--scan-csv', metavar='FILE',
                        help='also run obstacle_scan\'s camera scan: one row of LaserScan '
                             'ranges per frame (columns: stamp, then each bin\'s angle in rad)')
    parser.add_argument('--camera-height', type=float, metavar='M',
                        help='height of camera_link above the floor (m), for frames the bag\'s TF '
                             'gives no camera pose (default: none, those frames get no range '
                             'or scan)')
    parser.add_argument('--camera-pitch-deg', type=float, default=25.0, metavar='DEG',
                        help='with --camera-height: camera pitch below the horizon (deg, '
                             'positive down; default: %(default)s)')
    parser.add_argument('--camera-x', type=float, default=CAMERA_FORWARD_M, metavar='M',
                        help='with --camera-height: distance of camera_link ahead of the base '
                             'frame (m; default: %(default)s)')
    parser.add_argument('--param', action='append', default=[], metavar='NAME=VALUE',
                        help='override an image_converter or obstacle_scan parameter '
                             '(repeatable), e.g. green_max_ratio=0.4 or floor_model=dark')
    return parser.parse_args(argv)


def read_overrides(pairs):
    """The image_converter parameters with NAME=VALUE overrides (bad ones warned, default)."""
    overrides = {}
    for pair in pairs:
        name, _, value = pair.partition('=')
        overrides['~' + name.strip()] = value.strip()
    known = {'~' + spec.name for spec in TOOL_PARAMS}
    for name in sorted(set(overrides) - known):
        print('bag_detect: unknown parameter %s ignored' % name[1:], file=sys.stderr)
    return read_params(TOOL_PARAMS, lambda name, default: overrides.get(name, default),
                       lambda text: print('bag_detect: ' + text, file=sys.stderr))


def choose_image_topic(topic_types, requested):
    """(topic, message type) to read images from, given the bag's {topic: message type}.

    ``requested`` None means the default topic, or else the bag's only image topic of a type in
    MESSAGE_DECODERS. Raises SystemExit with the bag's image topics when there is no such choice.
    """
    image_topics = sorted(topic for topic, msg_type in topic_types.items()
                          if msg_type in MESSAGE_DECODERS)
    listed = ', '.join('%s (%s)' % (topic, topic_types[topic]) for topic in image_topics) or 'none'
    topic = requested or DEFAULT_IMAGE_TOPIC
    if requested is None and topic not in topic_types and len(image_topics) == 1:
        topic = image_topics[0]
    if topic not in topic_types:
        raise SystemExit('bag_detect: no topic %s in the bag; its image topics: %s (choose one '
                         'with --image-topic)' % (topic, listed))
    if topic_types[topic] not in MESSAGE_DECODERS:
        raise SystemExit('bag_detect: %s holds %s, expected %s; the bag\'s image topics: %s' % (
            topic, topic_types[topic], ' or '.join(sorted(MESSAGE_DECODERS)), listed))
    return topic, topic_types[topic]


def choose_camera_info_topic(topic_types, image_topic, requested):
    """The CameraInfo topic to read, given the bag's {topic: message type}, or None.

    ``requested`` None means camera_info in the image topic's namespace (image_transport's
    layout: ``/ns/image_raw`` and ``/ns/image/compressed`` have ``/ns/camera_info``), or else
    the bag's only CameraInfo topic."""
    if requested is not None:
        return requested if topic_types.get(requested) == CAMERA_INFO_TYPE else None
    base = image_topic.rstrip('/')
    if topic_types.get(base) in MESSAGE_DECODERS and base.endswith('/compressed'):
        base = base[:-len('/compressed')]
    beside = base.rpartition('/')[0] + '/camera_info'
    info_topics = sorted(topic for topic, msg_type in topic_types.items()
                         if msg_type == CAMERA_INFO_TYPE)
    if beside in info_topics:
        return beside
    return info_topics[0] if len(info_topics) == 1 else None


def report_row(stamp_s, report):
    """CSV values of one frame's CanReport."""
    return ('%.6f' % stamp_s, int(report.found), '%.2f' % report.centroid_x,
            '%.2f' % report.centroid_y, '%.0f' % report.area) + tuple(report.bbox) + (
        '%.4f' % report.range_m if math.isfinite(report.range_m) else 'nan',
        '%.4f' % report.bearing_rad if math.isfinite(report.bearing_rad) else 'nan',
        report.range_method, '%.3f' % report.confidence)


class BagDetector:
    """Runs the pipeline over the messages of one bag in recorded order."""

    def __init__(self, config, args, image_topic, image_type):
        self.config = config
        self.args = args
        self.image_topic = image_topic
        self.decode = MESSAGE_DECODERS[image_type]
        self.detector = RedCanDetector(DetectorSettings.from_values(config))
        self.can_model = CanModel()
        self.tf = tf2_ros.BufferCore(rospy.Duration(3600.0))
        mount_pose = (None if args.camera_height is None else camera_pose_from_mount(
            CameraMount(args.camera_height, args.camera_pitch_deg, args.camera_x)))
        self.camera_poses = CameraPoseSource.from_buffer_core(
            self.tf, config.base_frame, mount_pose, require_optical=True)
        self.image_rectified = config.image_rectified
        self.intrinsics = None
        self.video = None
        self.video_size = None
        self.skipped = {}
        self.without_pose = {}
        self.scanner = None
        self.scan_writer = None
        self.scan_header = None
        self.scanned = 0
        if args.scan_csv:
            self.scanner = CameraScanner(FloorSettings.from_values(config), config.max_range,
                                         config.exclude_can, robot_radius_m=config.robot_radius,
                                         robot_height_m=config.robot_height)
            self.scan_poses = CameraPoseSource.from_buffer_core(
                self.tf, config.scan_frame, mount_pose)

    def camera_pose(self, msg):
        """The camera pose by the nodes' rule, on the bag's clock (the image stamps); a frame
        without one is counted under the reason (``without_pose``: reason -> frames)."""
        return self.counted_pose(self.camera_poses, msg)

    def counted_pose(self, poses, msg):
        """The pose of ``msg``'s frame from ``poses`` (a CameraPoseSource), or None, counted
        under the reason with what supplies the pose (``without_pose``)."""
        frame_id = msg.header.frame_id.lstrip('/')
        pose = poses.pose(frame_id, msg.header.stamp.to_sec())
        if pose is None:
            # missing_transform names an empty frame_id's fault itself: no mount options then
            missing = missing_transform(poses.base_frame, frame_id)
            reason = poses.problems.get(frame_id) or (
                '%s in the bag; %s' % (missing, MOUNT_OPTIONS) if frame_id else missing)
            self.without_pose[reason] = self.without_pose.get(reason, 0) + 1
        return pose

    def on_image(self, msg, fps):
        """CanReport of one image message, or None when the frame cannot be read."""
        try:
            bgr = self.decode(msg)
        except NoColourError:
            return can_report((), msg.width, msg.height, None, None, self.can_model)
        except ImageDecodeError as error:
            reason = str(error).split(':')[0]
            self.skipped[reason] = self.skipped.get(reason, 0) + 1
            return None
        result = self.detector.detect(bgr)
        intrinsics = self.intrinsics
        height, width = bgr.shape[:2]
        if intrinsics is not None and (intrinsics.width, intrinsics.height) != (width, height):
            intrinsics = None
        report = can_report(result.candidates, width, height, self.camera_pose(msg),
                            intrinsics, self.can_model)
        scanned = bgr
        if self.scanner is not None:
            scan = self.scan(msg, bgr, intrinsics)
            if self.args.video:
                scanned = draw_obstacles(bgr, scan, self.scanner.floor.reference_corners)
        if self.args.video:
            self.write_video(draw_annotation(scanned, result, report.confidences, report.chosen,
                                             report.range_m), fps)
        return report

    def scan(self, msg, bgr, intrinsics):
        """obstacle_scan's camera scan of the frame; its ranges are one row of the scan CSV
        (a frame without camera geometry gets none)."""
        pose = self.counted_pose(self.scan_poses, msg)
        result = self.scanner.scan(bgr, pose if intrinsics else None, intrinsics)
        if result.ranges is not None:
            if self.scan_header is None:
                geometry = self.scanner.geometry
                self.scan_header = ['stamp'] + ['%.4f' % (geometry.angle_min + index *
                                                          geometry.angle_increment)
                                                for index in range(len(result.ranges))]
                self.scan_writer.writerow(self.scan_header)
            self.scan_writer.writerow(['%.6f' % msg.header.stamp.to_sec()] +
                                      ['%.3f' % value for value in result.ranges])
            self.scanned += 1
        return result

    def write_video(self, annotated, fps):
        """Append a frame; frames of another size than the first are left out of the video."""
        size = (annotated.shape[1], annotated.shape[0])
        if self.video is None:
            self.video_size = size
            self.video = cv2.VideoWriter(self.args.video, cv2.VideoWriter_fourcc(*'mp4v'), fps,
                                         size)
            if not self.video.isOpened():
                raise SystemExit('bag_detect: cannot write %s' % self.args.video)
        if size == self.video_size:
            self.video.write(annotated)

    def set_camera_info(self, msg):
        try:
            self.intrinsics = intrinsics_from_camera_info(
                msg.width, msg.height, msg.K, msg.D, msg.P, msg.distortion_model,
                self.image_rectified)
        except ValueError:
            self.intrinsics = None

    def add_transforms(self, msg, static):
        with warnings.catch_warnings():
            # Bag messages are generated classes, not geometry_msgs': tf2 warns, then copes.
            warnings.simplefilter('ignore', UserWarning)
            for transform in msg.transforms:
                if static:
                    self.tf.set_transform_static(transform, 'bag')
                else:
                    self.tf.set_transform(transform, 'bag')

    def run(self, bag, writer):
        """Static TF and the first camera_info first, so the first frames get a range too."""
        for _, msg, _ in bag.read_messages(topics=['/tf_static']):
            self.add_transforms(msg, static=True)
        info_topics = [self.args.camera_info_topic] if self.args.camera_info_topic else []
        for _, msg, _ in bag.read_messages(topics=info_topics) if info_topics else ():
            self.set_camera_info(msg)
            break
        topics = [self.image_topic, '/tf'] + info_topics
        image_count = bag.get_message_count(self.image_topic)
        duration_s = max(bag.get_end_time() - bag.get_start_time(), 1e-3)
        fps = max(1.0, min(120.0, image_count / duration_s))
        found = 0
        with tqdm(total=image_count, unit='frame', desc='bag_detect') as progress:
            for topic, msg, _ in bag.read_messages(topics=topics):
                if topic == '/tf':
                    self.add_transforms(msg, static=False)
                elif topic == self.args.camera_info_topic:
                    self.set_camera_info(msg)
                else:
                    report = self.on_image(msg, fps)
                    progress.update(1)
                    if report is not None:
                        writer.writerow(report_row(msg.header.stamp.to_sec(), report))
                        found += report.found
        if self.video is not None:
            self.video.release()
        return image_count, found


def main(argv=None):
    args = parse_args(rospy.myargv(sys.argv)[1:] if argv is None else argv)
    config = read_overrides(args.param)
    csv_path = args.csv or os.path.join(default_output_dir('bag_detect'), os.path.splitext(
        os.path.basename(args.bag))[0] + '.csv')
    os.makedirs(os.path.dirname(os.path.abspath(csv_path)), exist_ok=True)
    with rosbag.Bag(args.bag) as bag:
        topic_types = {topic: info.msg_type
                       for topic, info in bag.get_type_and_topic_info().topics.items()}
        image_topic, image_type = choose_image_topic(topic_types, args.image_topic)
        if args.image_topic is None and image_topic != DEFAULT_IMAGE_TOPIC:
            print('bag_detect: no %s in the bag; reading its only image topic, %s (%s)' % (
                DEFAULT_IMAGE_TOPIC, image_topic, image_type))
        info_topic = choose_camera_info_topic(topic_types, image_topic, args.camera_info_topic)
        if info_topic is None:
            print('bag_detect: no camera_info %sin the bag (its CameraInfo topics: %s): every '
                  'range and bearing is NaN and there is no camera scan; choose one with '
                  '--camera-info-topic' % (
                      args.camera_info_topic + ' ' if args.camera_info_topic else '',
                      ', '.join(sorted(topic for topic, msg_type in topic_types.items()
                                       if msg_type == CAMERA_INFO_TYPE)) or 'none'),
                  file=sys.stderr)
        elif args.camera_info_topic is None:
            print('bag_detect: camera_info from %s' % info_topic)
        args.camera_info_topic = info_topic
        detector = BagDetector(config, args, image_topic, image_type)
        with open(csv_path, 'w', newline='') as csv_file, \
                open(args.scan_csv or os.devnull, 'w', newline='') as scan_file:
            writer = csv.writer(csv_file)
            writer.writerow(CSV_COLUMNS)
            detector.scan_writer = csv.writer(scan_file)
            frames, found = detector.run(bag, writer)
    print('bag_detect: %d frames, can found in %d; CSV: %s%s' % (
        frames, found, csv_path, '; video: %s' % args.video if args.video else ''))
    if args.scan_csv:
        print('bag_detect: camera scan of %d frames (the others had no camera geometry): %s' % (
            detector.scanned, args.scan_csv))
    for reason, count in sorted(detector.without_pose.items()):
        print('bag_detect: %d frames without a camera pose (NaN range and bearing, no scan): '
              '%s' % (count, reason), file=sys.stderr)
    for reason, count in sorted(detector.skipped.items()):
        print('bag_detect: skipped %d of %d frames (no CSV row): %s' % (count, frames, reason),
              file=sys.stderr)
