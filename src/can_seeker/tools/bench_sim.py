"""bench_sim: real-time factor of the simulator, alone (no ROS) and as the ``sim`` node.

The node runs with ``real_time_factor:=0`` under its own master while this process subscribes to
/camera/image_raw (as a detector would), so publishing and transport count too; sim time is read
from the frames' stamps.
"""
import argparse
import os
import signal
import subprocess
import tempfile
import threading
import time

import rosgraph
import rospy
from sensor_msgs.msg import Image

from can_seeker.tools.closed_loop import free_port
from can_seeker.evaluation.sim_bench import CASES, run_case
from can_seeker.ros.paths import urdf_path
from can_seeker.sim.world import RENDERERS

STARTUP_TIMEOUT_S = 60.0
WARM_UP_S = 2.0


class NodeProbe:
    """(wall s, sim s) of the latest received frame and a count of received frames."""

    def __init__(self):
        self.lock = threading.Lock()
        self.forget()
        rospy.Subscriber('/camera/image_raw', Image, self._on_image, queue_size=1,
                         buff_size=2 ** 24)

    def _on_image(self, message):
        with self.lock:
            self.last_frame = (time.monotonic(), message.header.stamp.to_sec())
            self.frames += 1

    def forget(self):
        """Drop what was received so far (before the next launch)."""
        with self.lock:
            self.last_frame = None
            self.frames = 0

    def sample(self):
        """((wall s, sim s) of the latest frame, frames received so far)."""
        with self.lock:
            return self.last_frame, self.frames


def measure_node(probe, renderer, width, height, camera_rate_hz, duration_s, log,
                 world='empty', can_texture='plain'):
    """Launch sim.launch as fast as possible; (real-time factor, frames received per sim s)."""
    command = ['roslaunch', 'can_seeker', 'sim.launch', 'real_time_factor:=0',
               'renderer:=%s' % renderer, 'width:=%d' % width, 'height:=%d' % height,
               'camera_rate:=%g' % camera_rate_hz, 'world:=%s' % world,
               'can_texture:=%s' % can_texture]
    probe.forget()
    launch = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT,
                              start_new_session=True)
    try:
        deadline = time.monotonic() + STARTUP_TIMEOUT_S
        while probe.sample()[0] is None:
            if launch.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError('sim.launch did not start; see %s' % log.name)
            time.sleep(0.1)
        time.sleep(WARM_UP_S)
        (wall0_s, sim0_s), frames0 = probe.sample()
        time.sleep(duration_s)
        (wall1_s, sim1_s), frames1 = probe.sample()
        return (sim1_s - sim0_s) / (wall1_s - wall0_s), (frames1 - frames0) / (sim1_s - sim0_s)
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        launch.wait()


def main(argv=None):
    """Print the real-time factor of each camera configuration for the world and the node."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--renderer', choices=RENDERERS, default='auto',
                        help='camera renderer (default: auto, EGL with TinyRenderer fallback)')
    parser.add_argument('--duration', type=float, default=10.0,
                        help='sim time per world case, wall time per node case (s)')
    parser.add_argument('--no-node', action='store_true', help='benchmark the world only')
    args = parser.parse_args(argv)
    print('simulator benchmark: physics at 240 Hz, %d cores, %.0f s per case'
          % (os.cpu_count(), args.duration))
    print('| run | camera | world, can | renderer | real-time factor | target | '
          'render + convert (ms/frame) | physics + lidar (us/step) |')
    print('|---|---|---|---|---|---|---|---|')
    for width, height, rate_hz, target, world, texture in CASES:
        result = run_case(urdf_path(), args.renderer, width, height, rate_hz,
                          args.duration, world, texture)
        print('| world | %dx%d @ %g Hz | %s, %s | %s | %.2fx | >= %gx (%s) | %.1f | %.0f |'
              % (width, height, rate_hz, world, texture, result['renderer'],
                 result['real_time_factor'], target,
                 'met' if result['real_time_factor'] >= target else 'MISSED',
                 result['frame_ms'], result['step_us']))
    if args.no_node:
        return
    port = free_port()
    os.environ['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % port
    with tempfile.NamedTemporaryFile('w', prefix='bench_sim_', suffix='.log',
                                     delete=False) as log:
        master = subprocess.Popen(['roscore', '-p', str(port)], stdout=log,
                                  stderr=subprocess.STDOUT, start_new_session=True)
        try:
            deadline = time.monotonic() + STARTUP_TIMEOUT_S
            while not rosgraph.Master('/bench_sim').is_online():
                if time.monotonic() > deadline:
                    raise RuntimeError('roscore did not start; see %s' % log.name)
                time.sleep(0.1)
            rospy.init_node('bench_sim', anonymous=True, disable_signals=True)
            probe = NodeProbe()
            for width, height, rate_hz, target, world, texture in CASES:
                factor, frames_per_s = measure_node(probe, args.renderer, width, height,
                                                    rate_hz, args.duration, log, world, texture)
                print('| node | %dx%d @ %g Hz | %s, %s | %s | %.2fx | >= %gx (%s) | %.1f '
                      'frames/s received | |' % (width, height, rate_hz, world, texture,
                                                 args.renderer, factor, target,
                                                 'met' if factor >= target else 'MISSED',
                                                 frames_per_s))
        finally:
            rospy.signal_shutdown('benchmark done')
            os.killpg(master.pid, signal.SIGINT)
            master.wait()
