"""ROS node ``sim``: the pybullet world as a camera robot with a lidar on a floor (in an empty
world, a room with obstacles or a world file) with a soda can.

Publishes /clock (every physics step, or at ~clock_rate and with every other message),
/camera/image_raw + /camera/camera_info (same stamp: the sim time the frame was captured; with
~realism/preset and its knobs, published later and as a real camera sees it), /scan (the
lidar), /odom and TF odom->base_link (the true pose at the ~realism/preset ideal, else wheel
odometry that drifts), static TF
base_link->camera_link->camera_optical_frame from the actual camera parameters and
base_link->base_scan (each frame name a parameter: ``~base_frame``, ``~odom_frame``,
``~camera_frame``, ``~optical_frame``, ``~lidar_frame``), and ground truth in ``~world_frame``:
/sim/base_pose_ground_truth (the true pose and twist), /sim/can_pose, /sim/contact and
/sim/contacts (whether and what the robot touched at any physics step since the previous message),
``bumper`` (std_msgs/Bool: whether the front half of the robot's body, ahead of base_link, touched
anything but the floor since the previous message: a bumper's contact sensing) and /sim/world (latched: the scene in the world-file format), and /diagnostics (sim time and pace,
lockstep time-outs, the age and rate of the commands, parameters set but not read).
Subscribes /cmd_vel, or in lockstep cmd_vel_stamped. Services /sim/reset, /sim/reset_trial,
/sim/place_can, /sim/new_world, /sim/pause_physics and /sim/unpause_physics run on the simulation
thread between physics steps (in lockstep, after the current frame was answered).
"""
import math
import time
import warnings

import rospy
import tf2_ros
import yaml
from geometry_msgs.msg import PoseStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, LaserScan, TimeReference
from std_msgs.msg import Bool, String, UInt32
from std_srvs.srv import Empty, EmptyResponse
from tf2_msgs.msg import TFMessage

from can_seeker.msg import Contacts
from can_seeker.sim.call_queue import CallQueue
from can_seeker.sim.lockstep import LockstepGate, header_stamp_s
from can_seeker.gui.display_check import X11_PROBE, display_problem
from can_seeker.health import WARN, InputMonitor
from can_seeker.opencv_threads import use_one_opencv_thread
from can_seeker.params import parse_topics, read_params, unread_health, unread_params
from can_seeker.ros.diagnostics import NodeDiagnostics
from can_seeker.ros.messages import camera_info, mount_transforms, odometry, transform_stamped
from can_seeker.ros.paths import robots_dir, urdf_path, worlds_dir
from can_seeker.sim.simulation import (PARAMS, Simulation, camera_spec, can_visible_from_start,
                                       checked_config, mount_for, scene_for)
from can_seeker.sim.status import RunStatus
from can_seeker.srv import (NewWorld, NewWorldResponse, PlaceCan, PlaceCanResponse, ResetTrial,
                            ResetTrialResponse)
from can_seeker.sim.world import World

SERVICE_TIMEOUT_S = 10.0
MAX_PACING_LAG_S = 0.5
"""When the loop falls this far behind the wall-clock pace (s), it stops trying to catch up."""
ERROR_THROTTLE_S = 5.0
HOLD_POLL_S = 0.05
"""While a frame waits for its answers, calls and shutdown are checked this often (s, wall)."""
PAUSED_POLL_S = 0.002
"""While paused, calls are checked this often (s, wall)."""
STAMPED_COMMAND_TOPIC = 'cmd_vel_stamped'
FRAME_DELIVERY_TOPIC = 'frame_delivery'
"""Lockstep: sensor_msgs/TimeReference per frame, stamped with the sim time the frame went out
(``time_ref``: the frame's capture stamp); a controller answers a late frame from the pose at
that time, whatever order its inputs arrived in."""
TRUTH_QUEUE_SIZE = 1000
"""Outgoing queue of /odom and the ground-truth topics (messages; about 20 s of sim time)."""
TF_QUEUE_SIZE = 100
"""Outgoing queue of /tf (tf2_ros.TransformBroadcaster's)."""


def _publisher(name, data_class, queue_size):
    """A rospy publisher; ``queue_size`` None writes each message to the subscribers' sockets
    within ``publish`` (rospy warns about None for publishers that did not choose it)."""
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        return rospy.Publisher(name, data_class, queue_size=queue_size)


def _private_param_names():
    """The names (without ``~``) of every parameter set in this node's private namespace."""
    prefix = rospy.get_name() + '/'
    return [name[len(prefix):] for name in rospy.get_param_names() if name.startswith(prefix)]


class SimNode:
    """Glue between ROS and a :class:`Simulation`; everything pybullet runs in :meth:`spin`."""

    def __init__(self):
        config = checked_config(read_params(PARAMS, rospy.get_param, rospy.logwarn),
                                rospy.logwarn, [worlds_dir()], [robots_dir()])
        self._unread_params = unread_params(PARAMS, _private_param_names())
        for _, message in self._unread_params:
            rospy.logwarn('sim: not read: %s', message)
        if config.gui:
            problem = display_problem(X11_PROBE)
            if problem:
                rospy.logwarn('sim: ~gui is true but %s: running headless' % problem)
                config.gui = False
        # Advertised before the world is built, which takes seconds: the other nodes' clock
        # status counts its publisher from their start.
        self._clock_pub = _publisher('/clock', Clock, None if config.lockstep else 10)
        spec = camera_spec(config)
        world = World(urdf_path(), spec, config.physics_rate, config.renderer, config.gui,
                      config.can_color, config.scene, config.can_texture, config.profile)
        rospy.loginfo('sim: %s world with %d walls and %d obstacles; rendering %dx%d at %.1f Hz '
                      'with %s; can at (%.3f, %.3f)', config.world, len(config.scene.walls),
                      len(config.scene.obstacles), config.width, config.height,
                      config.camera_rate, world.renderer_name, *config.can_position)
        self._config = config
        self._sim = Simulation.from_config(world, config)
        self._real_time_factor = config.real_time_factor
        self._calls = CallQueue()
        self._paused = False
        self._reset_s = self._sim.time_s
        self._gate = LockstepGate(config.lockstep_timeout) if config.lockstep else None
        self._camera_info = camera_info(spec.intrinsics, self._sim.realism.distortion,
                                        config.optical_frame)
        rospy.loginfo('sim: realism %s, robot %s', config.realism.preset,
                      config.profile.name if config.profile else 'built-in')

        # Ground truth is small and judged message by message: a short outgoing queue drops
        # part of the path when the sim runs faster than real time on a busy machine. In
        # lockstep, where the simulator waits for its nodes anyway, the clock, odometry, TF and
        # ground truth are written from this thread as they are published: rospy's queued
        # publishing hands every message for every subscriber to a thread of its own and yields
        # to it, most of this node's CPU time besides rendering.
        synchronous = self._gate is not None
        self._image_pub = rospy.Publisher('camera/image_raw', Image, queue_size=2)
        self._info_pub = rospy.Publisher('camera/camera_info', CameraInfo, queue_size=2)
        truth_queue = None if synchronous else TRUTH_QUEUE_SIZE
        self._odom_pub = _publisher('odom', Odometry, truth_queue)
        self._truth_pub = _publisher('~base_pose_ground_truth', Odometry, truth_queue)
        self._can_pose_pub = _publisher('~can_pose', PoseStamped, truth_queue)
        self._contact_pub = _publisher('~contact', Bool, truth_queue)
        self._contacts_pub = _publisher('~contacts', Contacts, truth_queue)
        self._bumper_pub = _publisher('bumper', Bool, truth_queue)
        self._tf_pub = _publisher('/tf', TFMessage, None if synchronous else TF_QUEUE_SIZE)
        self._world_pub = rospy.Publisher('~world', String, queue_size=1, latch=True)
        self._timeouts_pub = rospy.Publisher('~lockstep_timeouts', UInt32, queue_size=1,
                                             latch=True)
        if self._gate is not None:
            self._timeouts_pub.publish(UInt32(data=0))
        self._scan_pub = rospy.Publisher('scan', LaserScan, queue_size=5)
        self._delivery_pub = (_publisher(FRAME_DELIVERY_TOPIC, TimeReference, None)
                              if synchronous else None)
        self._scan = self._scan_template(self._sim.lidar, config.scan_rate, config.lidar_frame)
        self._static_broadcaster = tf2_ros.StaticTransformBroadcaster()
        self._publish_clock()
        self._publish_static_tf()
        self._publish_world()
        self._frames = 0
        self._run_status = RunStatus()
        command_topic = STAMPED_COMMAND_TOPIC if self._gate else 'cmd_vel'
        self._commands = InputMonitor(command_topic, config.cmd_timeout, WARN,
                                      topic=rospy.resolve_name(command_topic))
        self._lockstep_inputs = []
        if self._gate is None:
            rospy.Subscriber('cmd_vel', Twist, self._on_cmd_vel, queue_size=10)
        else:
            self._subscribe_lockstep(parse_topics(config.lockstep_topics))
        self._diagnostics = NodeDiagnostics(clock=False)
        self._diagnostics.add('simulation', self._health)
        self._diagnostics.add('commands', lambda: self._commands.health(self._sim.time_s))
        self._diagnostics.add('parameters', lambda: unread_health(self._unread_params))
        rospy.Service('~reset', Empty, self._on_reset)
        rospy.Service('~reset_trial', ResetTrial, self._on_reset_trial)
        rospy.Service('~place_can', PlaceCan, self._on_place_can)
        rospy.Service('~pause_physics', Empty, lambda _: self._set_paused(True))
        rospy.Service('~unpause_physics', Empty, lambda _: self._set_paused(False))
        rospy.Service('~new_world', NewWorld, self._on_new_world)
        self._diagnostics.start()

    def _health(self):
        """Sim time and pace, paused or not, lockstep time-outs (diagnostics thread)."""
        gate = self._gate
        return self._run_status.report(
            self._sim.time_s, time.monotonic(), self._paused, self._frames,
            None if gate is None else gate.timeouts, () if gate is None else gate.missing())

    @staticmethod
    def _scan_template(spec, rate_hz, frame_id):
        if spec is None:
            return None
        scan = LaserScan()
        scan.header.frame_id = frame_id
        scan.angle_min = spec.angle_min_rad
        scan.angle_max = spec.angle_max_rad
        scan.angle_increment = spec.angle_increment_rad
        scan.scan_time = 1.0 / rate_hz
        scan.range_min = spec.range_min_m
        scan.range_max = spec.range_max_m
        return scan

    def _publish_world(self):
        self._world_pub.publish(String(data=yaml.safe_dump(self._sim.world.scene.as_dict(),
                                                           sort_keys=False)))

    def _subscribe_lockstep(self, topics):
        """Await the stamped command and ``topics`` (any type that starts with a Header)."""
        command = rospy.Subscriber(STAMPED_COMMAND_TOPIC, TwistStamped,
                                   self._on_stamped_command, queue_size=10, tcp_nodelay=True)
        self._lockstep_inputs.append((command.resolved_name, command))
        for topic in topics:
            subscriber = rospy.Subscriber(topic, rospy.AnyMsg, self._on_lockstep_answer,
                                          callback_args=rospy.names.resolve_name(topic),
                                          queue_size=10, tcp_nodelay=True)
            self._lockstep_inputs.append((subscriber.resolved_name, subscriber))
        rospy.loginfo('sim: lockstep: each frame waits for %s (at most %.2f s)',
                      ', '.join(name for name, _ in self._lockstep_inputs),
                      self._gate.timeout_s)

    def _on_lockstep_answer(self, message, name):
        try:
            self._gate.answered(name, header_stamp_s(message._buff))
        except ValueError as error:
            rospy.logerr_throttle(ERROR_THROTTLE_S, 'sim: lockstep topic %s: %s' % (name, error))

    def _on_stamped_command(self, command: TwistStamped):
        stamp_s = command.header.stamp.to_sec()
        self._commands.received(self._sim.time_s, stamp_s)
        if stamp_s > self._reset_s:
            self._on_cmd_vel(command.twist)
        self._gate.answered(self._lockstep_inputs[0][0], stamp_s)

    def _awaited_inputs(self):
        """The lockstep inputs a frame waits for: those with a publisher, if anyone sees it."""
        if self._image_pub.get_num_connections() == 0:
            return ()
        return [name for name, subscriber in self._lockstep_inputs
                if subscriber.get_num_connections() > 0]

    def _set_paused(self, paused):
        self._calls.call(lambda: setattr(self, '_paused', paused), SERVICE_TIMEOUT_S)
        return EmptyResponse()

    def _on_cmd_vel(self, twist: Twist):
        if self._gate is None:
            self._commands.received(self._sim.time_s)
        linear_mps, angular_radps = twist.linear.x, twist.angular.z
        if not (math.isfinite(linear_mps) and math.isfinite(angular_radps)):
            rospy.logerr_throttle(ERROR_THROTTLE_S, 'sim: ignoring /cmd_vel with a non-finite '
                                  'velocity (%r, %r)' % (linear_mps, angular_radps))
            return
        self._calls.post(lambda: self._sim.command(linear_mps, angular_radps))

    def _on_reset(self, _request):
        try:
            self._calls.call(lambda: self._reset_trial(None), SERVICE_TIMEOUT_S)
        except TimeoutError as error:
            rospy.logerr('sim: reset failed: %s', error)
        return EmptyResponse()

    def _reset_trial(self, can_xy):
        """On the sim thread: reset, and say at which sim time it took effect."""
        success, message = self._sim.reset_trial(can_xy)
        self._reset_s = self._sim.time_s
        return success, message, self._reset_s

    def _on_reset_trial(self, request):
        can_xy = (request.can_x, request.can_y) if request.place_can else None
        try:
            success, message, reset_s = self._calls.call(lambda: self._reset_trial(can_xy),
                                                         SERVICE_TIMEOUT_S)
        except TimeoutError as error:
            success, message, reset_s = False, str(error), self._sim.time_s
        if not success:
            rospy.logerr_throttle(ERROR_THROTTLE_S, 'sim: reset_trial: %s' % message)
        return ResetTrialResponse(success, message, rospy.Time.from_sec(reset_s))

    def _on_place_can(self, request):
        try:
            success, message = self._calls.call(
                lambda: self._sim.place_can(request.x, request.y), SERVICE_TIMEOUT_S)
        except TimeoutError as error:
            success, message = False, str(error)
        if not success:
            rospy.logerr_throttle(ERROR_THROTTLE_S, 'sim: place_can: %s' % message)
        return PlaceCanResponse(success, message)

    def _publish_static_tf(self):
        """base_link -> camera_link (the world's mount) -> camera_optical_frame, and the lidar
        (latched, all in one message: a later one replaces it)."""
        config, mount = self._config, self._sim.world.camera.mount
        stamp = rospy.Time.from_sec(self._sim.time_s)
        self._static_broadcaster.sendTransform(
            mount_transforms(stamp, mount, config.base_frame, config.camera_frame,
                             config.optical_frame)
            + [transform_stamped(stamp, config.base_frame, config.lidar_frame,
                                 (0.0, 0.0, config.scan_height), (0.0, 0.0, 0.0, 1.0))])

    def _on_new_world(self, request):
        scene = scene_for(self._config, request.seed, rospy.logwarn)

        def rebuild():
            if self._config.randomize_mount:
                self._sim.world.set_mount(mount_for(self._config, request.seed))
                self._publish_static_tf()
            self._sim.set_scene(scene, request.seed)
            self._reset_s = self._sim.time_s
            self._publish_world()
        try:
            self._calls.call(rebuild, SERVICE_TIMEOUT_S)
        except TimeoutError as error:
            rospy.logerr('sim: new_world failed: %s', error)
            return NewWorldResponse(False, str(error), math.nan, math.nan, False)
        return NewWorldResponse(True, 'world from seed %d: %d obstacles, can at (%.3f, %.3f)'
                                % (request.seed, len(scene.obstacles), *scene.can_xy),
                                scene.can_xy[0], scene.can_xy[1],
                                can_visible_from_start(scene, self._sim.world.camera))

    def _publish_clock(self):
        self._clock_pub.publish(Clock(clock=rospy.Time.from_sec(self._sim.time_s)))

    def _publish_delivery(self, stamp, image_time_s):
        """Lockstep: the frame stamped ``image_time_s`` goes out now (``stamp``), and the state
        published with it is the newest there is until its answer came back."""
        delivery = TimeReference(time_ref=rospy.Time.from_sec(image_time_s), source='camera')
        delivery.header.stamp = stamp
        self._delivery_pub.publish(delivery)

    def _publish_image(self, image, stamp):
        message = Image()
        message.header.stamp = stamp
        message.header.frame_id = self._config.optical_frame
        message.height, message.width = image.shape[:2]
        message.encoding = self._sim.encoding
        message.step = message.width * 3
        message.data = image.tobytes()
        self._camera_info.header.stamp = stamp
        self._image_pub.publish(message)
        self._info_pub.publish(self._camera_info)

    def _publish_scan(self, ranges, stamp):
        self._scan.header.stamp = stamp
        self._scan.ranges = ranges.tolist()
        self._scan_pub.publish(self._scan)

    def _publish_state(self, stamp, touched, bumped):
        world = self._sim.world
        config = self._config
        robot = world.robot_state()
        truth = odometry(stamp, config.world_frame, config.base_frame, robot.position,
                         robot.orientation_xyzw, robot.linear_velocity, robot.angular_velocity)
        self._truth_pub.publish(truth)
        if self._sim.realism.spec.odometry_is_true:
            odom = odometry(stamp, config.odom_frame, config.base_frame, robot.position,
                            robot.orientation_xyzw, robot.linear_velocity,
                            robot.angular_velocity)
        else:
            estimate = self._sim.odometry()
            odom = odometry(stamp, config.odom_frame, config.base_frame,
                            (estimate.x_m, estimate.y_m, robot.position[2]),
                            (0.0, 0.0, math.sin(estimate.yaw_rad / 2.0),
                             math.cos(estimate.yaw_rad / 2.0)),
                            (estimate.linear_mps, 0.0, 0.0), (0.0, 0.0, estimate.angular_radps))
        self._odom_pub.publish(odom)
        pose = odom.pose.pose
        self._tf_pub.publish(TFMessage([transform_stamped(
            stamp, config.odom_frame, config.base_frame,
            (pose.position.x, pose.position.y, pose.position.z),
            (pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w))]))
        can_position, can_orientation = world.can_pose()
        can = PoseStamped()
        can.header.stamp = stamp
        can.header.frame_id = config.world_frame
        can.pose.position.x, can.pose.position.y, can.pose.position.z = can_position
        (can.pose.orientation.x, can.pose.orientation.y, can.pose.orientation.z,
         can.pose.orientation.w) = can_orientation
        self._can_pose_pub.publish(can)
        self._contact_pub.publish(Bool(data=bool(touched)))
        contacts = Contacts(objects=sorted(touched))
        contacts.header.stamp = stamp
        self._contacts_pub.publish(contacts)
        self._bumper_pub.publish(Bool(data=bool(bumped)))

    def _wait_for_answers(self) -> bool:
        """In lockstep, whether the held frame still waits for its answers (a timeout is
        warned about and counted, and lets the simulation go on)."""
        missing = self._gate.wait(HOLD_POLL_S)
        if missing is None:
            return True
        if missing:
            self._timeouts_pub.publish(UInt32(data=self._gate.timeouts))
            rospy.logwarn_throttle(
                ERROR_THROTTLE_S, 'sim: lockstep: no answer from %s within %.2f s at t=%.3f; '
                'stepping on (%d frames timed out so far)' % (
                    ', '.join(missing), self._gate.timeout_s, self._sim.time_s,
                    self._gate.timeouts))
        return False

    def spin(self):
        """Step, publish and pace until shutdown."""
        wall_start_s, sim_start_s = time.monotonic(), self._sim.time_s
        while not rospy.is_shutdown():
            if self._gate is not None and self._gate.holding and self._wait_for_answers():
                continue
            self._calls.run_pending()
            if self._paused:
                time.sleep(PAUSED_POLL_S)
                wall_start_s, sim_start_s = time.monotonic(), self._sim.time_s
                continue
            if self._sim.lidar is not None:
                self._sim.scan_wanted = self._scan_pub.get_num_connections() > 0
            result = self._sim.step()
            if result.clock_due:
                self._publish_clock()
            stamp = rospy.Time.from_sec(result.time_s)
            if result.scan is not None:
                self._publish_scan(result.scan, stamp)
            if result.image is not None:
                self._frames += 1
                if self._delivery_pub is not None:
                    self._publish_delivery(stamp, result.image_time_s)
                self._publish_image(result.image, rospy.Time.from_sec(result.image_time_s))
                if self._gate is not None:
                    self._gate.hold(result.image_time_s, self._awaited_inputs())
            if result.state_due or (self._gate is not None and result.image is not None):
                # In lockstep every frame also has its state: a controller answers the frame
                # once its odometry caught up with it.
                self._publish_state(stamp, result.touched, result.bumped)
            if self._real_time_factor > 0.0:
                lag_s = (time.monotonic() - wall_start_s
                         - (result.time_s - sim_start_s) / self._real_time_factor)
                if lag_s < 0.0:
                    time.sleep(-lag_s)
                elif lag_s > MAX_PACING_LAG_S:
                    wall_start_s, sim_start_s = time.monotonic(), result.time_s

    def close(self):
        """Release pybullet."""
        self._sim.world.close()


def main():
    """Run the ``sim`` node."""
    use_one_opencv_thread()
    rospy.init_node('sim')
    try:
        node = SimNode()
    except RuntimeError as error:
        rospy.logfatal('sim: %s', error)
        raise SystemExit(1)
    try:
        node.spin()
    finally:
        node.close()
