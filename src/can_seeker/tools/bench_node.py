"""bench_node: CPU time per frame of whole ROS nodes on one shared 30 Hz 640x480 bgr8 stream.

In one run, on its own master (free port), the same published stream feeds side by side:
opencv_apps' chain hsv_color_filter -> contour_moments + edge_detection (three C++ nodes, Debian
``ros-opencv-apps``), image_converter with every output subscribed (detection, annotated, mask,
edges), image_converter with only its detection subscribed, and two bare rospy nodes that
only receive the images and acknowledge each with an empty message: one subscribed and with the
allocator set as image_converter does (its cost is the receiving inside image_converter), one
with glibc's default allocator (a plain rospy node). Each process's CPU time
(utime + stime of /proc/<pid>/stat, all threads) over the frames it answered (its output
messages counted) gives milliseconds per frame; a chain's is the sum of its processes'. The run
is repeated and the load average printed: on 2 shared cores wall-clock latency says little,
CPU per frame much more (frames dropped under load are not counted). ``--result FILE`` writes
the medians as a result file for docs/results/.
"""
import argparse
import os
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import rosgraph
import rospy
import tf2_ros
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Empty

from can_seeker.allocator import reuse_freed_memory
from can_seeker.camera_geometry import intrinsics_from_vertical_fov
from can_seeker.camera_mount import CameraMount
from can_seeker.ros.messages import mount_transforms
from can_seeker.evaluation.result_files import command_line, result_record, write_result
from can_seeker.tools.bench_vision import floor_scene

IMAGE_TOPIC = '/bench/image_raw'
INFO_TOPIC = '/bench/camera_info'
FRAME = 'camera_optical_frame'
OPENCV_APPS_DIR = '/usr/lib/opencv_apps'
PLAIN_RECEIVER = 'plain rospy receiver (default allocator)'
CLOCK_TICKS_PER_S = os.sysconf('SC_CLK_TCK')
# Red as opencv_apps' hsv_color_filter takes it: hue in degrees, wrapping when min > max.
OPENCV_APPS_RED = ['_h_limit_min:=340', '_h_limit_max:=12', '_s_limit_min:=130',
                   '_v_limit_min:=50', '_use_camera_info:=false', '_debug_view:=false',
                   '_queue_size:=1']


def process_cpu_s(pid: int) -> float:
    """User + system CPU time (s) a process has used so far, all its threads included."""
    with open('/proc/%d/stat' % pid) as stat:
        fields = stat.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS_PER_S


def wait_for_master(timeout_s):
    deadline = time.time() + timeout_s
    while not rosgraph.is_master_online():
        if time.time() > deadline:
            raise SystemExit('bench_node: the master did not start')
        time.sleep(0.2)


def free_port():
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def receiver_main(reuse_memory=True):
    """A bare receiver: a rospy node that takes the images as image_converter does (same
    subscriber options; with ``reuse_memory`` the same allocator setting) and answers each with
    an empty message (so its frames can be counted like the others')."""
    if reuse_memory:
        reuse_freed_memory()
    rospy.init_node('bare_receiver')
    ack = rospy.Publisher('~received', Empty, queue_size=10)
    rospy.Subscriber('image', Image, lambda _msg: ack.publish(Empty()), queue_size=1,
                     buff_size=2 ** 24)
    rospy.spin()


class Counter:
    """Counts messages of one topic without deserialising them."""

    def __init__(self, topic):
        self.count = 0
        self.lock = threading.Lock()
        self.subscriber = rospy.Subscriber(topic, rospy.AnyMsg, self.on_message, queue_size=10,
                                           buff_size=2 ** 24)

    def on_message(self, _msg):
        with self.lock:
            self.count += 1


def start_nodes(env, with_opencv_apps):
    """{name: [(Popen, the output topic counting its frames), ...]} of every node under test;
    the processes of one name are measured together."""
    def start(arguments):
        return subprocess.Popen(arguments, env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
    nodes = {}
    if with_opencv_apps:
        chain = [(start([os.path.join(OPENCV_APPS_DIR, 'hsv_color_filter'),
                         'image:=' + IMAGE_TOPIC, '__name:=hsv_color_filter'] + OPENCV_APPS_RED),
                  '/hsv_color_filter/image'),
                 (start([os.path.join(OPENCV_APPS_DIR, 'contour_moments'),
                         'image:=/hsv_color_filter/image', '__name:=contour_moments',
                         '_use_camera_info:=false',
                         '_debug_view:=false', '_queue_size:=1']), '/contour_moments/moments'),
                 (start([os.path.join(OPENCV_APPS_DIR, 'edge_detection'),
                         'image:=' + IMAGE_TOPIC, '__name:=edge_detection',
                         '_use_camera_info:=false', '_debug_view:=false', '_queue_size:=1']),
                  '/edge_detection/image')]
        nodes['opencv_apps chain (3 nodes)'] = chain
    converter = ['rosrun', 'can_seeker', 'image_converter', 'image:=' + IMAGE_TOPIC,
                 'camera_info:=' + INFO_TOPIC]
    nodes['image_converter, all outputs'] = [(start(converter + ['__name:=converter_all']),
                                              '/converter_all/detection')]
    nodes['image_converter, detection only'] = [
        (start(converter + ['__name:=converter_detect']), '/converter_detect/detection')]
    for name, node, reuse_memory in (('bare rospy receiver', 'bare_receiver', True),
                                     (PLAIN_RECEIVER, 'plain_receiver', False)):
        nodes[name] = [(start([sys.executable, '-c', 'from can_seeker.tools.bench_node import '
                               'receiver_main; receiver_main(%s)' % reuse_memory,
                               'image:=' + IMAGE_TOPIC, '__name:=' + node]),
                        '/%s/received' % node)]
    return nodes


def subscribe_outputs(with_opencv_apps):
    """Counters on every output a node under test is asked for (they also make the lazy
    opencv_apps nodes and image_converter's debug outputs work)."""
    topics = ['/converter_all/detection', '/converter_all/annotated', '/converter_all/mask',
              '/converter_all/edges', '/converter_detect/detection', '/bare_receiver/received',
              '/plain_receiver/received']
    if with_opencv_apps:
        topics += ['/hsv_color_filter/image', '/contour_moments/moments', '/edge_detection/image']
    return {topic: Counter(topic) for topic in topics}


def publish_frames(publisher, msg, frames, rate_hz):
    start = time.time()
    for index in range(frames):
        msg.header.stamp = rospy.Time.from_sec(time.time())
        publisher.publish(msg)
        time.sleep(max(0.0, start + (index + 1) / rate_hz - time.time()))


def measure(nodes, counters, publisher, msg, frames, rate_hz):
    """({node: CPU ms per frame it answered}, {topic: messages received}) over one window."""
    processes = [entry for entries in nodes.values() for entry in entries]
    cpu_before = {process.pid: process_cpu_s(process.pid) for process, _ in processes}
    counts_before = {topic: counter.count for topic, counter in counters.items()}
    publish_frames(publisher, msg, frames, rate_hz)
    time.sleep(1.0)
    received = {topic: counter.count - counts_before[topic] for topic, counter in counters.items()}
    per_frame = {}
    for name, entries in nodes.items():
        per_frame[name] = sum(1e3 * (process_cpu_s(process.pid) - cpu_before[process.pid])
                              / max(1, received[topic]) for process, topic in entries)
    return per_frame, received


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--frames', type=int, default=300, help='frames per window (default 300)')
    parser.add_argument('--repeats', type=int, default=3, help='windows (default 3)')
    parser.add_argument('--rate', type=float, default=30.0, help='frame rate (Hz, default 30)')
    parser.add_argument('--result', metavar='FILE', help='write the medians with this command, '
                        'the commit and the machine as a result file (docs/results/NAME.json)')
    command_argv = sys.argv[1:] if argv is None else argv
    args = parser.parse_args(command_argv)
    with_opencv_apps = os.path.isfile(os.path.join(OPENCV_APPS_DIR, 'hsv_color_filter'))
    if not with_opencv_apps:
        print('bench_node: opencv_apps is not installed (Debian: ros-opencv-apps '
              'libopencv-apps-dev libopencv-apps2d libnodeletlib-dev): measuring without it')
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port)
    os.environ.update(env)
    master = subprocess.Popen(['roscore', '-p', str(port)], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    nodes = {}
    try:
        wait_for_master(60.0)
        rospy.init_node('bench_node', disable_signals=True)
        tf2_ros.StaticTransformBroadcaster().sendTransform(
            mount_transforms(rospy.Time(0), CameraMount(0.25, 25.0), optical_frame=FRAME))
        width, height = 640, 480
        intrinsics = intrinsics_from_vertical_fov(width, height, 45.0)
        info = CameraInfo(width=width, height=height, K=intrinsics.K, P=intrinsics.P)
        info.header.frame_id = FRAME
        info_pub = rospy.Publisher(INFO_TOPIC, CameraInfo, queue_size=1, latch=True)
        info_pub.publish(info)
        image = floor_scene(width, height)
        msg = Image(height=height, width=width, encoding='bgr8', step=width * 3,
                    data=image.tobytes())
        msg.header.frame_id = FRAME
        publisher = rospy.Publisher(IMAGE_TOPIC, Image, queue_size=1)
        nodes = start_nodes(env, with_opencv_apps)
        counters = subscribe_outputs(with_opencv_apps)
        expected = 6 if with_opencv_apps else 4
        deadline = time.time() + 60.0
        while publisher.get_num_connections() < expected and time.time() < deadline:
            time.sleep(0.2)
        publish_frames(publisher, msg, int(3 * args.rate), args.rate)  # warm-up
        time.sleep(1.0)
        print('CPU ms per frame, %dx%d bgr8 at %.0f Hz, %d frames per window; load average '
              'before: %s' % (width, height, args.rate, args.frames, os.getloadavg()))
        names = list(nodes)
        print('| window | ' + ' | '.join(names) + ' | load (1 min) |')
        print('|---' * (len(names) + 2) + '|')
        windows, clean = [], []
        for window in range(args.repeats):
            per_frame, received = measure(nodes, counters, publisher, msg, args.frames,
                                          args.rate)
            windows.append(per_frame)
            print('| %d | ' % (window + 1) + ' | '.join('%.2f' % per_frame[name]
                                                        for name in names)
                  + ' | %.1f |' % os.getloadavg()[0])
            short = {topic: count for topic, count in received.items()
                     if count < 0.9 * args.frames}
            if short:
                print('  answered fewer than 90%% of the %d frames: %s' % (args.frames, short))
            else:
                clean.append(per_frame)
        # Frames dropped under load were still received: they would inflate the cost per frame.
        chosen = clean or windows
        median = {name: float(np.median([window[name] for window in chosen]))
                  for name in names}
        print('| median of %d %s | ' % (len(chosen), 'windows without drops' if clean else
                                        'windows (all had drops)')
              + ' | '.join('%.2f' % median[name] for name in names) + ' | |')
        bare = median['bare rospy receiver']
        detection = median['image_converter, detection only']
        print('\ndetection only - bare receive: %.2f ms per frame (target <= 1.5); against the '
              'plain rospy receiver: %.2f' % (detection - bare, detection - median[PLAIN_RECEIVER]))
        if with_opencv_apps:
            print('all outputs / opencv_apps chain: %.2f (target <= 0.6)' % (
                median['image_converter, all outputs'] / median['opencv_apps chain (3 nodes)']))
        load_after = os.getloadavg()
        print('load average after: %s' % (load_after,))
        if args.result:
            write_result(args.result, result_record('bench_node', command_line('bench_node',
                                                                               command_argv), {
                'ms_per_frame': median, 'windows': len(windows),
                'windows_without_drops': len(clean), 'frames_per_window': args.frames,
                'rate_hz': args.rate, 'load_average_after': load_after[0]}))
            print('result written to %s' % args.result)
        rospy.signal_shutdown('benchmark done')
    finally:
        processes = [process for entries in nodes.values() for process, _ in entries]
        for process in processes:
            process.terminate()
        for process in processes:
            process.wait(timeout=10)
        master.terminate()
        master.wait(timeout=10)
