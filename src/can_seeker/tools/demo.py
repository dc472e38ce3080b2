"""demo: one headless closed-loop run in a room with the can at a random pose, recorded.

Starts the simulator, image_converter, obstacle_scan and can_stopper under their own master
(demo.launch on a free port), builds the world of ``--seed`` (printed; pass it again to repeat
the run: by default a room with obstacles and the can anywhere in it), waits until the robot has
stopped or the time limit, then writes to ``--output`` (by default ``demo_output`` in the
workspace's or the ROS home, see :mod:`can_seeker.output_paths`): ``demo.mp4`` (annotated camera
next to a top-down view of the room, the floor covered so far, the path and the can),
``trajectory.png``, ``summary.json`` and ``index.html`` (the three side by side, for a browser),
and prints the summary and the folder. Times are sim time.
"""
import argparse
import json
import os
import random
import sys
import threading

import cv2
import numpy as np
import rospy
import yaml
from cv_bridge import CvBridge, CvBridgeError
from nav_msgs.msg import OccupancyGrid
from sensor_msgs.msg import Image
from std_msgs.msg import String

from can_seeker.tools.closed_loop import LaunchedSystem, TrialRunner
from can_seeker.params import defaults
from can_seeker.sim.realism import REALISM_PRESETS
from can_seeker.sim.scene import scene_from_dict
from can_seeker.sim.simulation import PARAMS as SIM_PARAMS
from can_seeker.sim.world import CAN_TEXTURES
from can_seeker.evaluation.topdown import (CoverageMap, TopDownView, draw_topdown, scene_points,
                                           plot_trajectory, side_by_side)
from can_seeker.evaluation.sweep import override_arg
from can_seeker.evaluation.trials import Criteria, json_ready
from can_seeker.evaluation.demo_page import write_demo_page
from can_seeker.output_paths import default_output_dir
from can_seeker.evaluation.video import Mp4Writer

VIDEO_HEIGHT_PX = 480
DEMO_WORLD = 'room'
"""The demo shows the whole behaviour: a room with obstacles, the can anywhere in it."""
VIEW_MARGIN_M = 0.6
SIM = defaults(SIM_PARAMS)


def parse_args(argv):
    parser = argparse.ArgumentParser(prog='demo', description=__doc__.split('\n\n')[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--seed', type=int, default=None,
                        help='seed of the can placement (default: a random one, printed)')
    parser.add_argument('--output', default=default_output_dir('demo_output'),
                        help='output directory')
    parser.add_argument('--min-distance', type=float, default=SIM.can_min_distance,
                        help='nearest can centre from the robot start (m)')
    parser.add_argument('--max-distance', type=float, default=SIM.can_max_distance,
                        help='farthest can centre from the robot start (m)')
    parser.add_argument('--world', default=DEMO_WORLD,
                        help='empty, room or a YAML world file (a path or a name in worlds/); '
                        'rooms and the can are drawn from the seed')
    parser.add_argument('--can-texture', default=SIM.can_texture, choices=CAN_TEXTURES,
                        help='textured soda can or plain red')
    parser.add_argument('--time-limit', type=float, default=Criteria.time_limit_s,
                        help='sim time allowed to reach STOPPED (s)')
    parser.add_argument('--real-time-factor', type=float, default=1.0,
                        help='sim speed; 0 runs as fast as possible')
    parser.add_argument('--realism', default=SIM.realism.preset, choices=REALISM_PRESETS,
                        help='sensor and actuator realism preset of the simulator '
                        '(sim/realism/preset)')
    parser.add_argument('--param', action='append', default=[], type=override_arg,
                        metavar='NODE/PARAM=VALUE',
                        help='set a parameter of sim, image_converter, obstacle_scan or '
                        'can_stopper, e.g. sim/realism/camera_latency_s=0.1 (repeatable)')
    return parser.parse_args(argv)


class VideoRecorder:
    """Annotated camera frames from image_converter, each next to the top-down view of the
    moment (with can_stopper's map of covered floor and sensed obstacles), into an MP4 at the
    camera rate."""

    def __init__(self, filename, fps, monitor, view, criteria, scene):
        self.writer = Mp4Writer(filename, fps)
        self.scene = scene
        self.monitor = monitor
        self.view = view
        self.criteria = criteria
        self.bridge = CvBridge()
        self.lock = threading.Lock()
        self.closed = False
        self.coverage = None
        rospy.Subscriber('can_stopper/coverage', OccupancyGrid, self.on_coverage, queue_size=1)
        rospy.Subscriber('image_converter/annotated', Image, self.on_image, queue_size=5,
                         buff_size=2 ** 24)

    def on_coverage(self, grid):
        info = grid.info
        values = np.array(grid.data, np.int8).reshape(info.height, info.width)
        self.coverage = CoverageMap(info.origin.position.x, info.origin.position.y,
                                    info.resolution, values)

    def on_image(self, message):
        try:
            camera = self.bridge.imgmsg_to_cv2(message, desired_encoding='bgr8')
        except (CvBridgeError, TypeError) as error:
            rospy.logerr_throttle(5.0, 'demo: cannot convert the annotated image: %s' % error)
            return
        scale = max(1, VIDEO_HEIGHT_PX // camera.shape[0])
        camera = cv2.resize(camera, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)
        pose, can_xy, _, path, _ = self.monitor.snapshot()
        if pose is None or can_xy is None:
            return
        caption = 't %.1f s  %s' % (message.header.stamp.to_sec() - self.monitor.start_s,
                                    self.monitor.state or '')
        top = draw_topdown(self.view, path, pose, can_xy, self.criteria.robot_radius_m,
                           self.criteria.can_radius_m, caption, self.coverage, self.scene)
        with self.lock:
            if not self.closed:
                self.writer.write(side_by_side(camera, top))

    def close(self):
        with self.lock:
            self.closed = True
            return self.writer.close()


def main():
    try:
        run(parse_args(rospy.myargv()[1:]))
    except KeyboardInterrupt:
        print('demo: interrupted', file=sys.stderr)
        sys.exit(130)


def run(args):
    """The demo run; exits 1 when the robot did not stop in tolerance."""
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(2 ** 31)
    print('demo: seed %d (repeat with --seed %d, or make demo SEED=%d)' % (seed, seed, seed))
    os.makedirs(args.output, exist_ok=True)
    world = args.world
    if world not in ('empty', 'room') and os.path.exists(world):
        world = os.path.abspath(world)
    launch = {'can_placement': 'random', 'seed': seed, 'world': world,
              'can_min_distance': args.min_distance, 'can_max_distance': args.max_distance,
              'can_texture': args.can_texture, 'real_time_factor': args.real_time_factor,
              'realism': args.realism}
    with LaunchedSystem(launch, os.path.join(args.output, 'roslaunch.log'),
                        params=dict(args.param)) as system:
        rospy.init_node('demo', disable_signals=True)
        system.wait_for_services()
        criteria = Criteria(stop_distance_m=rospy.get_param('can_stopper/stop_distance'),
                            time_limit_s=args.time_limit)
        runner = TrialRunner(criteria)
        can_xy, visible = runner.new_world(seed)
        scene = scene_from_dict(yaml.safe_load(
            rospy.wait_for_message('sim/world', String, timeout=30.0).data))
        print('demo: %s world, %d obstacles; the can at (%.2f, %.2f) is %s from the start'
              % (args.world, len(scene.obstacles), can_xy[0], can_xy[1],
                 'in view' if visible else 'not in view'))
        view = TopDownView.framing([(0.0, 0.0), can_xy] + scene_points(scene), VIDEO_HEIGHT_PX,
                                   VIEW_MARGIN_M)
        recorder = VideoRecorder(os.path.join(args.output, 'demo.mp4'),
                                 rospy.get_param('sim/camera_rate'), runner.monitor, view,
                                 criteria, scene)
        result = runner.run(0, can_xy, visible)
        video_ok = recorder.close()
        pose, final_can, _, path, _ = runner.monitor.snapshot()
        rospy.signal_shutdown('demo done')
    plot_trajectory(os.path.join(args.output, 'trajectory.png'), path, pose, final_can,
                    criteria.robot_radius_m, criteria.can_radius_m, criteria.stop_distance_m,
                    'seed %d: gap %.3f m (target %.2f), bearing %.1f deg'
                    % (seed, result.gap_m, criteria.stop_distance_m, result.bearing_deg), scene)
    summary = {'seed': seed, 'can_x_m': can_xy[0], 'can_y_m': can_xy[1],
               'stopped': result.stopped, 'time_to_stop_s': result.time_to_stop_s,
               'final_gap_m': result.gap_m, 'target_gap_m': criteria.stop_distance_m,
               'gap_error_m': result.gap_m - criteria.stop_distance_m,
               'bearing_deg': result.bearing_deg, 'path_length_m': result.path_length_m,
               'contact': result.contact, 'contact_objects': result.contact_objects,
               'first_contact_s': result.first_contact_s,
               'first_contact_pose': [result.first_contact_x_m, result.first_contact_y_m,
                                      result.first_contact_yaw_deg],
               'can_visible_from_start': visible, 'world': args.world,
               'success': result.success,
               'video_frames': recorder.writer.frames if video_ok else 0}
    with open(os.path.join(args.output, 'summary.json'), 'w') as output:
        json.dump(json_ready(summary), output, indent=2, allow_nan=False)
    page = write_demo_page(args.output, json_ready(summary))
    time_text = ('%.1f s' % result.time_to_stop_s if result.stopped
                 else 'not stopped within %.0f s' % args.time_limit)
    print('demo: can at (%.2f, %.2f) m; final gap %.3f m (target %.2f, error %+.1f mm), '
          'bearing %+.2f deg, time to stop %s (sim), path %.2f m, contact %s -> %s'
          % (can_xy[0], can_xy[1], result.gap_m, criteria.stop_distance_m,
             1000.0 * summary['gap_error_m'], result.bearing_deg, time_text,
             result.path_length_m,
             result.contact_text(),
             'SUCCESS' if result.success else 'FAILED'))
    print('demo: wrote demo.mp4 (%d frames), trajectory.png, summary.json and index.html to\n'
          '  %s\nopen %s in a browser to see the run'
          % (summary['video_frames'], os.path.abspath(args.output), os.path.abspath(page)))
    sys.exit(0 if result.success else 1)
