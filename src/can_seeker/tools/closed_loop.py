"""Closed-loop runs of the real nodes: start them under their own master, watch the ground truth,
run trials through the sim and controller services.

A trial starts atomically: the simulator is paused, the controller reset, the robot and the can
reset in one service call that says at which sim time it took effect, and the simulator
unpaused; the monitors record from exactly that time. At the end the simulator is paused again,
so the final state is measured on a still world.

Shared by ``scripts/evaluate``, ``scripts/demo`` and the closed-loop rostests. Ground truth comes
from the simulator: ``sim/base_pose_ground_truth`` (true base pose; ``odom`` is the robot's
own estimate, which drifts with ``realism``), ``sim/can_pose``, ``sim/contact`` and
``sim/contacts`` (what was touched); ``sim/lockstep_timeouts`` counts the frames a lockstep
simulator stepped on without their answers. In rooms and world files each trial first rebuilds
the world from its seed (``sim/new_world``). Topic and service names are relative: a monitor
in the robot's namespace (``<group ns="robot1">``) watches that robot.
"""
import math
import os
import signal
import socket
import subprocess
import threading
import time
from xml.sax.saxutils import quoteattr

import rosgraph
import rospy
from geometry_msgs.msg import PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
from roslaunch.rlutil import resolve_launch_arguments
from std_msgs.msg import Bool, String, UInt32
from std_srvs.srv import Empty

from can_seeker.msg import Contacts
from can_seeker.srv import NewWorld, PlaceCan, ResetTrial
from can_seeker.camera_geometry import yaw_from_quaternion
from can_seeker.evaluation.clock_watch import ClockWatch
from can_seeker.evaluation.trials import Contact, judge, path_length, pose_at, until

STATE_TOPIC = 'can_stopper/state'
TRUE_POSE_TOPIC = 'sim/base_pose_ground_truth'
COMMAND_TOPIC = 'cmd_vel_stamped'
LIVE_TIMEOUT_S = 60.0
SERVICES = ('sim/reset_trial', 'sim/place_can', 'sim/new_world', 'sim/pause_physics',
            'sim/unpause_physics',
            'can_stopper/reset', 'obstacle_scan/reset')
POLL_S = 0.01
SETTLE_S = 0.5
"""Sim time (s) between STOPPED and the measurement, for the base to come to rest."""
TRUTH_WAIT_S = 2.0
"""How long a trial's judge waits for the true poses up to the trial's end (wall s)."""
SIM_STALL_S = 30.0
"""Wall time (s) with the sim clock standing still after which a wait for sim time gives up:
the simulator died or hung (see :class:`ClockWatch`)."""
LAUNCH_GUARD = ('while kill -0 "$1" 2>/dev/null; do sleep 1; done; '
                'kill -INT -"$2" 2>/dev/null && sleep 20 && kill -KILL -"$2" 2>/dev/null')
"""sh script ``guard OWNER_PID LAUNCH_PGID``: once the owner process is gone (killed, so it
could not stop its launch), stop the launch's process group as :meth:`LaunchedSystem.__exit__`
would."""
WARM_UP_S = 1.0
"""Sim time (s) the controller has to have been commanding before the first trial: by then
every node has its TF and camera_info (a node without them yet falls back to its parameters,
and the first trial would depend on when they came)."""


def free_port() -> int:
    """A TCP port nobody listens on right now."""
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def parameter_launch(params, path):
    """Write a launch file to ``path`` that sets each ``/node/param`` of ``params`` (loaded
    after demo.launch, so its values win over the launch file's)."""
    lines = ['<launch>'] + ['  <param name=%s value=%s/>' % (quoteattr(name), quoteattr(str(value)))
                            for name, value in sorted(params.items())] + ['</launch>']
    with open(path, 'w') as output:
        output.write('\n'.join(lines) + '\n')


class LaunchedSystem:
    """``roslaunch can_seeker demo.launch`` with its own master on a free port.

    A context manager: on entry ROS_MASTER_URI points at the new master (for this process and
    the launch) and its parameters are set, so ``rospy.init_node`` sees ``/use_sim_time``; on
    exit the whole launch (its process group) is stopped; a guard process stops it too if
    this process is killed first. ``params`` (``/node/param`` -> value) override any node
    parameter, also those demo.launch has no argument for. ``env``: environment variables
    added to this process's for roslaunch and every node it starts.
    """

    def __init__(self, launch_args, log_path, startup_timeout_s=60.0, params=None, env=None):
        self.launch_args = dict(launch_args)
        self.log_path = log_path
        self.startup_timeout_s = startup_timeout_s
        self.params = dict(params or {})
        self.env = dict(env or {})
        self.process = None
        self.guard = None
        self.log = None

    def __enter__(self):
        port = free_port()
        uri = 'http://127.0.0.1:%d' % port
        os.environ['ROS_MASTER_URI'] = uri
        command = ['roslaunch', '-p', str(port)]
        if self.params:
            params_path = self.log_path + '.params.launch'
            parameter_launch(self.params, params_path)
            command += [resolve_launch_arguments(['can_seeker', 'demo.launch'])[0], params_path]
        else:
            command += ['can_seeker', 'demo.launch']
        command += ['%s:=%s' % item for item in sorted(self.launch_args.items())]
        self.log = open(self.log_path, 'w')
        self.process = subprocess.Popen(command, stdout=self.log, stderr=subprocess.STDOUT,
                                        env=dict(os.environ, **self.env),
                                        start_new_session=True)
        self.guard = subprocess.Popen(['sh', '-c', LAUNCH_GUARD, 'launch_guard', str(os.getpid()),
                                       str(self.process.pid)], start_new_session=True)
        deadline = time.monotonic() + self.startup_timeout_s
        master = rosgraph.Master('/closed_loop')
        while not (master.is_online() and master.hasParam('/use_sim_time')):
            self._check_alive(deadline)
            time.sleep(0.1)
        return self

    def _check_alive(self, deadline):
        if self.process.poll() is not None:
            raise RuntimeError('roslaunch exited with %s; see %s'
                               % (self.process.returncode, self.log_path))
        if time.monotonic() > deadline:
            raise RuntimeError('the nodes did not come up in %.0f s; see %s'
                               % (self.startup_timeout_s, self.log_path))

    def wait_for_services(self):
        """Block until the sim and controller services exist (or raise)."""
        deadline = time.monotonic() + self.startup_timeout_s
        for service in SERVICES:
            while True:
                self._check_alive(deadline)
                try:
                    rospy.wait_for_service(service, 1.0)
                    break
                except rospy.ROSException:
                    continue

    def __exit__(self, *exc_info):
        if self.process is not None and self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGINT)
            try:
                self.process.wait(20.0)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait()
        if self.guard is not None:
            self.guard.kill()
            self.guard.wait()
        if self.log is not None:
            self.log.close()


class TruthMonitor:
    """Subscribes to the ground truth and the controller state; keeps what one trial needs.

    Messages stamped at or before :meth:`start` (still in flight from before a reset) are
    ignored.
    The truth topics are queued without limit: on a busy machine a bounded queue would drop
    the older part of the path.
    """

    def __init__(self):
        self.lock = threading.Lock()
        self.start(0.0)
        self.commanding = threading.Event()
        self.first_command_s = None
        self.lockstep_timeouts = None
        self.subscribers = [
            rospy.Subscriber(TRUE_POSE_TOPIC, Odometry, self._on_true_pose, queue_size=None),
            rospy.Subscriber('sim/can_pose', PoseStamped, self._on_can_pose, queue_size=None),
            rospy.Subscriber('sim/contact', Bool, self._on_contact, queue_size=None),
            rospy.Subscriber('sim/contacts', Contacts, self._on_contacts, queue_size=None),
            rospy.Subscriber(STATE_TOPIC, String, self._on_state, queue_size=10),
            rospy.Subscriber(COMMAND_TOPIC, TwistStamped, self._on_command, queue_size=1),
            rospy.Subscriber('sim/lockstep_timeouts', UInt32, self._on_lockstep_timeouts,
                             queue_size=10),
        ]

    def _on_command(self, message):
        stamp_s = message.header.stamp.to_sec()
        if self.first_command_s is None:
            self.first_command_s = stamp_s
        elif stamp_s - self.first_command_s >= WARM_UP_S:
            self.commanding.set()

    def _on_lockstep_timeouts(self, message):
        with self.lock:
            self.lockstep_timeouts = message.data

    def wait_until_live(self, timeout_s):
        """Block until every truth topic is connected and the controller has commanded for
        WARM_UP_S (the camera -> detector -> controller chain runs); RuntimeError after
        ``timeout_s``.

        Before that, the start of a trial could be missed: a subscription still being
        connected silently loses the first messages.
        """
        deadline = time.monotonic() + timeout_s
        while not (all(subscriber.get_num_connections() > 0 for subscriber in self.subscribers)
                   and self.commanding.is_set()):
            if time.monotonic() > deadline:
                raise RuntimeError('the ground truth or the controller did not come up within '
                                   '%.0f s' % timeout_s)
            time.sleep(POLL_S)

    def start(self, now_s):
        """Forget the previous trial: record what is stamped after sim time ``now_s``."""
        with self.lock:
            self.start_s = now_s
            self.stamped_poses = []
            self.can_xy = None
            self.contact_s = None
            self.contact_objects = set()
            self.first_contact = None
            self.state = None
            self.stopped_s = None
            self.seen_search = False

    def _on_true_pose(self, message):
        if message.header.stamp.to_sec() <= self.start_s:
            return
        position = message.pose.pose.position
        orientation = message.pose.pose.orientation
        pose = (position.x, position.y, yaw_from_quaternion(
            orientation.x, orientation.y, orientation.z, orientation.w))
        with self.lock:
            self.stamped_poses.append((message.header.stamp.to_sec(),) + pose)

    def _on_can_pose(self, message):
        if message.header.stamp.to_sec() > self.start_s:
            with self.lock:
                self.can_xy = (message.pose.position.x, message.pose.position.y)

    def _on_contact(self, message):
        now_s = rospy.get_time()
        if message.data and now_s > self.start_s:
            with self.lock:
                if self.contact_s is None:
                    self.contact_s = now_s

    def _on_contacts(self, message):
        stamp_s = message.header.stamp.to_sec()
        if message.objects and stamp_s > self.start_s:
            with self.lock:
                self.contact_objects.update(message.objects)
                if self.first_contact is None or stamp_s < self.first_contact[0]:
                    self.first_contact = (stamp_s, sorted(message.objects))

    def _on_state(self, message):
        with self.lock:
            self.state = message.data
            if message.data == 'SEARCH':
                self.seen_search = True
            elif message.data == 'STOPPED' and self.seen_search and self.stopped_s is None:
                self.stopped_s = rospy.get_time()

    def contact_record(self):
        """The trial's first contact (time since the start, true pose then, objects), or None."""
        with self.lock:
            if self.first_contact is None:
                return None
            stamp_s, objects = self.first_contact
            pose = pose_at(self.stamped_poses, stamp_s) or (float('nan'),) * 3
            return Contact(stamp_s - self.start_s, pose[0], pose[1], pose[2], objects)

    def wait_for_truth(self, end_s, timeout_s=TRUTH_WAIT_S):
        """Wait (up to ``timeout_s`` of wall time) until a true pose stamped at or after sim
        time ``end_s`` has come: the poses up to ``end_s`` are all in."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            with self.lock:
                if self.stamped_poses and self.stamped_poses[-1][0] >= end_s:
                    return
            time.sleep(POLL_S)

    def snapshot(self, end_s=math.inf):
        """(pose, can_xy, contact, path, stopped_s) of the trial up to sim time ``end_s`` (a
        trial ends at a sim time of its own, not whenever its end is noticed): the true pose
        then, whether anything was touched by then and the path so far."""
        with self.lock:
            pose, path = until(self.stamped_poses, end_s)
            contact = self.contact_s is not None and self.contact_s <= end_s
            return pose, self.can_xy, contact, path, self.stopped_s


class TrialRunner:
    """Runs trials on a running system: an atomic start (see the module), wait for STOPPED (or
    the time limit, sim time), let the base settle, pause, judge on truth."""

    def __init__(self, criteria):
        self.criteria = criteria
        self.monitor = TruthMonitor()
        self.reset_trial = rospy.ServiceProxy('sim/reset_trial', ResetTrial, persistent=True)
        self.place_can = rospy.ServiceProxy('sim/place_can', PlaceCan)
        self.pause = rospy.ServiceProxy('sim/pause_physics', Empty, persistent=True)
        self.unpause = rospy.ServiceProxy('sim/unpause_physics', Empty, persistent=True)
        self.reset_controller = rospy.ServiceProxy('can_stopper/reset', Empty, persistent=True)
        self.reset_obstacle_scan = rospy.ServiceProxy('obstacle_scan/reset', Empty,
                                                      persistent=True)
        self.new_world_service = rospy.ServiceProxy('sim/new_world', NewWorld)
        self.timeouts_at_start = None

    def new_world(self, seed):
        """Rebuild the simulator's world from ``seed`` (paused; :meth:`run` starts the trial);
        ((can x, can y) in odom (m), whether the start camera sees the can)."""
        self.monitor.wait_until_live(LIVE_TIMEOUT_S)
        self.pause()
        response = self.new_world_service(seed)
        if not response.success:
            raise RuntimeError('new_world(%d) failed: %s' % (seed, response.message))
        return (response.can_x, response.can_y), response.can_visible_from_start

    def start(self, can_xy):
        """Start a trial with the can centre at ``can_xy`` (odom, m); its start in sim time (s).

        Paused, nothing moves and no frame is taken while the controller and the scene are
        reset, so the trial begins exactly at the reset, with the robot where it was put. The
        first start waits until the system is live (so it needs a running simulator); the
        lockstep time-outs so far are taken then, so those of the system's startup are not the
        trial's.
        """
        self.monitor.wait_until_live(LIVE_TIMEOUT_S)
        self.pause()
        with self.monitor.lock:
            self.timeouts_at_start = self.monitor.lockstep_timeouts
        reset = self.reset_trial(True, can_xy[0], can_xy[1])
        if not reset.success:
            self.unpause()
            raise RuntimeError('reset_trial with the can at (%.3f, %.3f) failed: %s'
                               % (can_xy[0], can_xy[1], reset.message))
        start_s = reset.stamp.to_sec()
        self.monitor.start(start_s)
        self.reset_controller()
        self.reset_obstacle_scan()
        self.unpause()
        return start_s

    def wait_sim(self, duration_s, done=lambda: False):
        """Sleep ``duration_s`` of sim time, or until ``done()``; False if ROS shut down.
        RuntimeError when the sim clock stands still for ``SIM_STALL_S`` of wall time: the
        simulator died (the trial then runs again on a fresh system, see engine.run_trial)."""
        start_s = rospy.get_time()
        end_s = start_s + duration_s
        watch = ClockWatch(SIM_STALL_S, start_s, time.monotonic())
        while rospy.get_time() < end_s and not done():
            if rospy.is_shutdown():
                return False
            if watch.stalled(rospy.get_time(), time.monotonic()):
                raise RuntimeError('the sim clock has stood still at %.3f s for %.0f s of wall '
                                   'time: the simulator died or hung' % (watch.sim_s,
                                                                         SIM_STALL_S))
            time.sleep(POLL_S)
        return True

    def run(self, index, can_xy, can_visible_from_start=None):
        """One trial with the can centre at ``can_xy`` (odom, m); returns a TrialResult.

        The simulator stays paused afterwards (the next :meth:`start` unpauses it).
        """
        start_wall = time.monotonic()
        start_s = self.start(can_xy)
        self.wait_sim(self.criteria.time_limit_s, lambda: self.monitor.stopped_s is not None)
        end_s = start_s + self.criteria.time_limit_s
        if self.monitor.stopped_s is not None:
            end_s = self.monitor.stopped_s + SETTLE_S
            self.wait_sim(SETTLE_S)
        self.pause()
        self.monitor.wait_for_truth(end_s)
        pose, final_can, contact, path, stopped_s = self.monitor.snapshot(end_s)
        if pose is None or final_can is None:
            raise RuntimeError('no ground truth from the simulator (%s, %s)'
                               % (rospy.resolve_name(TRUE_POSE_TOPIC),
                                  rospy.resolve_name('sim/can_pose')))
        time_to_stop = None if stopped_s is None else stopped_s - start_s
        with self.monitor.lock:
            contact_objects = sorted(self.monitor.contact_objects)
            timeouts = (None if self.monitor.lockstep_timeouts is None else
                        self.monitor.lockstep_timeouts - (self.timeouts_at_start or 0))
        return judge(index, can_xy, time_to_stop, pose[:2], pose[2], final_can, contact,
                     path_length(path), end_s - start_s,
                     time.monotonic() - start_wall, self.criteria, contact_objects,
                     can_visible_from_start, self.monitor.contact_record(), timeouts)
