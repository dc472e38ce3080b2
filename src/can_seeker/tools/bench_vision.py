"""bench_vision: per-frame cost of the red can pipeline and its ROS end-to-end latency.

Part 1 times, on a synthetic floor scene with a red can, our pipeline (red mask, clean-up,
largest blob, moments, Canny edges, range and bearing) against the classic image_converter
tutorial callback (HSV, inRange, bitwise_and, moments, Canny on grey, three half-size resizes)
at 320x240, 640x480 and 1280x720, with OpenCV on one thread and on its default threads.
Part 2 times the camera obstacle scan (floor classification, can exclusion, per-column bases,
scan bins) with the adaptive floor model (without and with its white-balance correction) and
the tutorial's dark threshold, beside the tutorial's obstacle callback (grey, threshold, findContours, largest contour, boundingRect).
Part 3 starts its own master on a free port and an image_converter node, publishes 640x480
bgr8 frames at 30 Hz and then as fast as possible, and measures stamp -> detection received.
The numbers depend on the machine's load: rerun on an idle machine for reference values.
"""
import argparse
import os
import socket
import subprocess
import sys
import threading
import time

import cv2
import numpy as np
import rospy
import tf2_ros
from sensor_msgs.msg import CameraInfo, Image

from can_seeker.camera_geometry import camera_pose_from_mount, intrinsics_from_vertical_fov
from can_seeker.camera_mount import CameraMount
from can_seeker.ros.messages import mount_transforms
from can_seeker.vision.report import CanModel, can_report
from can_seeker.msg import CanDetection
from can_seeker.vision.camera_scan import CameraScanner
from can_seeker.vision.detector import RedCanDetector
from can_seeker.vision.floor import FloorSettings

SIZES = ((320, 240), (640, 480), (1280, 720))
TUTORIAL_RED_LOW = (0, 120, 70)
TUTORIAL_RED_HIGH = (10, 255, 255)

MOUNT = CameraMount(0.25, 25.0)
"""The camera mount of every part: the simulated robot's."""


def floor_scene(width, height, seed=0):
    """A grey-brown floor with a lighting gradient, texture noise and an upright red can."""
    rng = np.random.default_rng(seed)
    rows = np.linspace(0.6, 1.0, height, dtype=np.float32)[:, None, None]
    image = np.array((90, 110, 125), np.float32) * rows * np.ones((1, width, 1), np.float32)
    image += rng.normal(0.0, 6.0, image.shape)
    image = np.clip(image, 0, 255).astype(np.uint8)
    cv2.rectangle(image, (0, 0), (width - 1, height // 3), (200, 205, 210), -1)
    can_x, can_y = int(width * 0.58), int(height * 0.45)
    can_w, can_h = max(6, width // 18), max(12, height // 7)
    cv2.rectangle(image, (can_x, can_y), (can_x + can_w, can_y + can_h), (30, 25, 190), -1)
    cv2.ellipse(image, (can_x + can_w // 2, can_y + can_h), (can_w // 2, max(2, can_w // 5)),
                0, 0, 180, (30, 25, 190), -1)
    left, top = width // 8, height // 2
    cv2.rectangle(image, (left, top), (left + width // 10, top + height // 10), (40, 120, 200), -1)
    return image


def tutorial_callback(bgr):
    """The image_converter tutorial's work per frame (the windows' resizes included)."""
    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
    mask = cv2.inRange(hsv, TUTORIAL_RED_LOW, TUTORIAL_RED_HIGH)
    result = cv2.bitwise_and(bgr, bgr, mask=mask)
    moments = cv2.moments(mask)
    centre = (moments['m10'] / moments['m00'], moments['m01'] / moments['m00']) \
        if moments['m00'] > 0 else None
    edges = cv2.Canny(cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY), 100, 200)
    half = (bgr.shape[1] // 2, bgr.shape[0] // 2)
    return centre, [cv2.resize(image, half) for image in (bgr, result, edges)]


def our_pipeline(detector, pose, intrinsics):
    def run(bgr):
        result = detector.detect(bgr, want_edges=True)
        return can_report(result.candidates, bgr.shape[1], bgr.shape[0], pose, intrinsics,
                          CanModel())
    return run


def time_per_frame_ms(function, image, frames):
    """Median and 95th percentile of per-call wall time (ms) after a short warm-up."""
    for _ in range(5):
        function(image)
    samples = np.empty(frames)
    for index in range(frames):
        start = time.perf_counter()
        function(image)
        samples[index] = time.perf_counter() - start
    return 1e3 * np.median(samples), 1e3 * np.percentile(samples, 95)


def bench_frames(frames):
    print('Per-frame cost (ms; median / p95), %d frames each' % frames)
    print('| size | threads | ours (edges on) | tutorial callback | tutorial / ours |')
    print('|---|---|---|---|---|')
    default_threads = cv2.getNumThreads()
    for threads in (1, default_threads):
        cv2.setNumThreads(threads)
        for width, height in SIZES:
            image = floor_scene(width, height)
            pipeline = our_pipeline(RedCanDetector(), camera_pose_from_mount(MOUNT),
                                    intrinsics_from_vertical_fov(width, height, 45.0))
            assert pipeline(image).found, 'the benchmark scene must contain a visible can'
            ours = time_per_frame_ms(pipeline, image, frames)
            tutorial = time_per_frame_ms(tutorial_callback, image, frames)
            print('| %dx%d | %d | %.2f / %.2f | %.2f / %.2f | %.2f |' % (
                width, height, threads, ours[0], ours[1], tutorial[0], tutorial[1],
                tutorial[0] / ours[0]))
    cv2.setNumThreads(default_threads)


def obstacle_scene(width, height):
    """floor_scene with two dark boxes and a light cylinder standing on the floor."""
    image = floor_scene(width, height)
    for left, top, right, bottom, colour in ((0.05, 0.35, 0.3, 0.6, (35, 35, 40)),
                                              (0.7, 0.4, 0.95, 0.55, (40, 30, 30)),
                                              (0.42, 0.38, 0.5, 0.52, (225, 225, 220))):
        cv2.rectangle(image, (int(left * width), int(top * height)),
                      (int(right * width), int(bottom * height)), colour, -1)
    return image


def tutorial_obstacle_callback(bgr):
    """The obstacle tutorial's work per frame: dark pixels, largest contour, its box."""
    grey = cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY)
    _, dark = cv2.threshold(grey, 60, 255, cv2.THRESH_BINARY_INV)
    contours, _ = cv2.findContours(dark, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    return cv2.boundingRect(max(contours, key=cv2.contourArea)) if contours else None


def bench_obstacle_scan(frames):
    print('\nCamera obstacle scan per frame (ms; median / p95), %d frames each, OpenCV on %d '
          'threads' % (frames, cv2.getNumThreads()))
    print('| size | adaptive floor model | adaptive, max_colour_shift 0.3 | dark threshold | '
          'tutorial obstacle callback |')
    print('|---|---|---|---|---|')
    pose = camera_pose_from_mount(MOUNT)
    for width, height in SIZES:
        image = obstacle_scene(width, height)
        intrinsics = intrinsics_from_vertical_fov(width, height, 45.0)
        cells = []
        for settings in (FloorSettings(), FloorSettings(max_colour_shift=0.3),
                         FloorSettings(floor_model='dark')):
            scanner = CameraScanner(settings)
            result = scanner.scan(image, pose, intrinsics)
            assert np.isfinite(result.ranges).any(), 'the benchmark scene must hold obstacles'
            cells.append(time_per_frame_ms(lambda bgr: scanner.scan(bgr, pose, intrinsics),
                                           image, frames))
        cells.append(time_per_frame_ms(tutorial_obstacle_callback, image, frames))
        print('| %dx%d | %s |' % (width, height, ' | '.join('%.2f / %.2f' % cell
                                                          for cell in cells)))


def free_port():
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def latency_stats(samples_s):
    samples_ms = 1e3 * np.asarray(samples_s)
    return 'median %.1f, p95 %.1f, p99 %.1f, max %.1f ms' % (
        np.median(samples_ms), np.percentile(samples_ms, 95), np.percentile(samples_ms, 99),
        samples_ms.max())


class LatencyProbe:
    """Publishes frames (and the camera mount, MOUNT, on /tf_static) to a running
    image_converter and times their detections."""

    def __init__(self, width, height):
        self.tf = tf2_ros.StaticTransformBroadcaster()
        self.tf.sendTransform(mount_transforms(rospy.Time(0), MOUNT))
        intrinsics = intrinsics_from_vertical_fov(width, height, 45.0)
        image = floor_scene(width, height)
        self.frame = Image(height=height, width=width, encoding='bgr8', step=width * 3,
                           data=image.tobytes())
        self.frame.header.frame_id = 'camera_optical_frame'
        info = CameraInfo(width=width, height=height, K=intrinsics.K, P=intrinsics.P)
        info.header.frame_id = 'camera_optical_frame'
        self.info_pub = rospy.Publisher('/camera/camera_info', CameraInfo, queue_size=1, latch=True)
        self.info_pub.publish(info)
        self.image_pub = rospy.Publisher('/camera/image_raw', Image, queue_size=1)
        self.lock = threading.Lock()
        self.latencies = []
        self.debug_subscribers = []
        rospy.Subscriber('/image_converter/detection', CanDetection, self.on_detection,
                         queue_size=100)

    def on_detection(self, msg):
        received = time.time()
        with self.lock:
            self.latencies.append(received - msg.header.stamp.to_sec())

    def subscribe_debug_images(self):
        """Make the node build ~annotated, ~mask and ~edges too (more work per frame)."""
        for topic in ('annotated', 'mask', 'edges'):
            self.debug_subscribers.append(rospy.Subscriber(
                '/image_converter/' + topic, Image, lambda _msg: None, queue_size=1,
                buff_size=2 ** 24))

    def wait_connected(self, timeout_s=30.0):
        deadline = time.time() + timeout_s
        while self.image_pub.get_num_connections() == 0:
            if time.time() > deadline:
                raise SystemExit('bench_vision: image_converter did not subscribe')
            time.sleep(0.05)
        time.sleep(1.0)

    def run(self, rate_hz, duration_s):
        """Publish for ``duration_s`` at ``rate_hz`` (0: as fast as possible); returns
        (frames sent, latencies)."""
        with self.lock:
            self.latencies = []
        sent = 0
        start = time.time()
        period = 1.0 / rate_hz if rate_hz > 0 else 0.0
        while time.time() - start < duration_s and not rospy.is_shutdown():
            self.frame.header.stamp = rospy.Time.from_sec(time.time())
            self.image_pub.publish(self.frame)
            sent += 1
            if period:
                time.sleep(max(0.0, start + sent * period - time.time()))
        time.sleep(0.5)
        with self.lock:
            return sent, list(self.latencies)


def bench_latency(duration_s):
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port)
    os.environ.update(env)
    processes = [subprocess.Popen(['roscore', '-p', str(port)], env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        time.sleep(2.0)
        processes.append(subprocess.Popen(
            ['rosrun', 'can_seeker', 'image_converter', 'image:=/camera/image_raw',
             'camera_info:=/camera/camera_info'], env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL))
        rospy.init_node('bench_vision', disable_signals=True)
        probe = LatencyProbe(640, 480)
        probe.wait_connected()
        print('\nROS end-to-end latency, 640x480 bgr8, image stamp -> detection received')
        sent, latencies = probe.run(30.0, duration_s)
        print('- 30 Hz: %d frames sent, %d detections; %s' % (
            sent, len(latencies), latency_stats(latencies)))
        probe.subscribe_debug_images()
        time.sleep(1.0)
        sent, latencies = probe.run(0.0, duration_s)
        third = max(1, len(latencies) // 3)
        print('- overloaded (as fast as possible, with ~annotated, ~mask, ~edges subscribed): '
              '%.0f Hz sent, %.0f Hz processed; %s; median first third %.1f ms, last third '
              '%.1f ms (equal = no backlog)' % (
                  sent / duration_s, len(latencies) / duration_s, latency_stats(latencies),
                  1e3 * np.median(latencies[:third]), 1e3 * np.median(latencies[-third:])))
        rospy.signal_shutdown('benchmark done')
    finally:
        for process in reversed(processes):
            process.terminate()
            process.wait(timeout=10)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--frames', type=int, default=300, help='frames per timing (default 300)')
    parser.add_argument('--latency-seconds', type=float, default=6.0,
                        help='duration of each latency run (s, default 6)')
    parser.add_argument('--no-ros', action='store_true', help='skip the ROS latency part')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    bench_frames(args.frames)
    bench_obstacle_scan(args.frames)
    if not args.no_ros:
        bench_latency(args.latency_seconds)
