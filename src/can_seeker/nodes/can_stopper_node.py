"""can_stopper: drive the robot to the can seen by image_converter and stop just in front of it.

Subscribes ``detection`` (can_seeker/CanDetection; remap it to image_converter's
``~detection``), ``camera_info`` (sensor_msgs/CameraInfo, for the floor the camera covers),
``~odom_topic`` (nav_msgs/Odometry) and every topic of ``~scan_topics`` (sensor_msgs/LaserScan
of obstacles, any frame in TF; sensor poses in ``~base_frame`` from
:mod:`can_seeker.ros.camera_pose`) and, with ``~lockstep``, ``frame_delivery``
(sensor_msgs/TimeReference from the simulator: when each frame was published); publishes
``cmd_vel`` (geometry_msgs/Twist) and ``cmd_vel_stamped`` (geometry_msgs/TwistStamped, the
same command stamped with the time it is for) from a fixed-rate timer, or with ``~lockstep``
once per detection, stamped like its image;
``~state`` (std_msgs/String, latched: IDLE while disarmed); ``~coverage`` (nav_msgs/OccupancyGrid, latched, once a
second) and, for rviz while subscribed, ``~obstacle_grid`` (nav_msgs/OccupancyGrid of the
obstacle memory: 100 obstacle, 0 observed floor, -1 unknown; latched), ``~path``
(nav_msgs/Path, the planned path, empty when none) and ``~markers``
(visualization_msgs/MarkerArray: the can estimate, the state over the robot), all in
``~odom_frame``; ``/diagnostics`` (each input's rate and age, the state and why the command
is zero or limited); ``~reset`` (std_srvs/Empty) returns to SEARCH and forgets the map;
``~enable`` (std_srvs/SetBool) arms (SEARCH afresh, as ``~reset``) and disarms (IDLE: zero
commands at once); with ``~bumper_topic`` it subscribes that std_msgs/Bool (a press stops the
robot at once, then the bump recovery backs it off). The
behaviour is :mod:`can_seeker.control.controller`. Invalid safety bounds among the parameters
stop the node at start (exit status 1); every control tick ends in a published command, zero
when anything in it failed; a missing or stale input is warned about, throttled per input.
"""
import math
import sys
import threading
import time

import numpy as np
import rospy
from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from sensor_msgs.msg import CameraInfo, LaserScan, TimeReference
from std_msgs.msg import Bool, String
from std_srvs.srv import Empty, EmptyResponse, SetBool, SetBoolResponse
from visualization_msgs.msg import MarkerArray

from can_seeker.camera_geometry import intrinsics_from_k, yaw_from_quaternion
from can_seeker.control.controller import PARAMS, Controller
from can_seeker.control.input_freshness import problems_text
from can_seeker.control.sighting import (camera_floor_pose, detection_problem,
                                         sighting_from_detection)
from can_seeker.control.frame_inputs import FrameInputs
from can_seeker.control.navigation import Pose2D, camera_view
from can_seeker.control.scan_points import scan_rays
from can_seeker.control.tick_guard import TickGuard
from can_seeker.control.tuning import controller_settings
from can_seeker.control.twist_limits import ZERO, require_finite
from can_seeker.health import ERROR, OK, WARN, Health, InputMonitor
from can_seeker.msg import CanDetection
from can_seeker.params import UnsafeParamError, read_params
from can_seeker.ros.camera_pose import (PUBLISH_HINT, UNSTAMPED, CameraPoseSource,
                                        missing_transform)
from can_seeker.ros.sensor_tf import SensorTf
from can_seeker.ros.diagnostics import NodeDiagnostics
from can_seeker.ros.messages import (controller_markers, occupancy_grid, path_msg, twist,
                                     twist_stamped)
from can_seeker.throttle import KindThrottle

COVERAGE_PERIOD_S = 1.0
VIEW_PERIOD_S = 0.5
"""~obstacle_grid, ~path and ~markers (for rviz, while subscribed) go out this often (s)."""
LOCKSTEP_QUEUE = 100
"""Odometry and scan messages kept in lockstep (a few arrive per camera frame)."""
MISSING_INPUT_LOG_PERIOD_S = 5.0
"""A missing or stale input is warned about at most this often, per input (s)."""
SHUTDOWN_ZERO_COUNT = 5
SHUTDOWN_ZERO_SPACING_S = 0.02


class CanStopperNode:
    """Glue between ROS and :class:`can_seeker.control.controller.Controller`."""

    def __init__(self, params):
        """``params``: the controller's settings (controller_settings of the read PARAMS)."""
        self.params = params
        self.controller = Controller(
            params, camera_info_topic=rospy.resolve_name('camera_info'),
            arm_hint='rosservice call %s true' % rospy.resolve_name('~enable'))
        self.guard = TickGuard(lambda message: rospy.logerr('can_stopper: %s' % message))
        self.lock = threading.Lock()
        self.shutting_down = False
        self.tf = SensorTf(warn=lambda message: rospy.logwarn('can_stopper: %s' % message))
        # Camera and scan sensors alike: their poses come from TF only.
        self.sensor_poses = CameraPoseSource.from_tf(
            self.tf, params.base_frame, name='can_stopper',
            without='a detection in that frame gives the can\'s side, no range; a scan in it '
                    'is dropped')
        self.cmd_pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
        self.stamped_cmd_pub = rospy.Publisher('cmd_vel_stamped', TwistStamped, queue_size=10)
        self.state_pub = rospy.Publisher('~state', String, queue_size=1, latch=True)
        self.coverage_pub = rospy.Publisher('~coverage', OccupancyGrid, queue_size=1, latch=True)
        self.obstacle_grid_pub = rospy.Publisher('~obstacle_grid', OccupancyGrid, queue_size=1,
                                                 latch=True)
        self.path_pub = rospy.Publisher('~path', Path, queue_size=1)
        self.markers_pub = rospy.Publisher('~markers', MarkerArray, queue_size=1)
        self.coverage_s = -float('inf')
        self.view_s = -float('inf')
        self.odom_frame = params.odom_frame
        self.camera_pose_logged = set()
        self.camera_pose_missing = ''
        self.intrinsics = None
        self.logged_view = None
        self.published_state = None
        self.publish_state()
        self.missing_input_log = KindThrottle(MISSING_INPUT_LOG_PERIOD_S)
        params = self.params
        # Missing, an input the controller needs is an error, one it could use a warning.
        self.monitors = {
            'detection': InputMonitor('detection', params.detection_timeout,
                                      WARN if self.controller.wander else ERROR,
                                      topic=rospy.resolve_name('detection')),
            'odometry': InputMonitor('odometry', params.odom_timeout,
                                     ERROR if self.controller.senses_obstacles else WARN,
                                     topic=rospy.resolve_name(params.odom_topic)),
            'camera_info': InputMonitor('camera_info', params.camera_info_timeout,
                                        ERROR if self.controller.needs_camera_info else WARN,
                                        topic=rospy.resolve_name('camera_info'))}
        if params.bumper_topic:
            # Bumpers report on a change, or at a rate: silence is no fault.
            self.monitors['bumper'] = InputMonitor('bumper', missing_level=OK,
                                                   topic=rospy.resolve_name(params.bumper_topic))
        self.monitors.update({topic: InputMonitor('scan %s' % topic, params.scan_timeout,
                                                  topic=rospy.resolve_name(topic))
                              for topic in self.controller.scan_sources})
        rospy.Service('~reset', Empty, self.on_reset)
        rospy.Service('~enable', SetBool, self.on_enable)
        if params.bumper_topic:
            rospy.Subscriber(params.bumper_topic, Bool, self.on_bumper, queue_size=10,
                             tcp_nodelay=True)
        rospy.Subscriber('camera_info', CameraInfo, self.on_camera_info, queue_size=1)
        # Lockstep keeps every odometry and scan message: the answers must not depend on which
        # ones a busy machine would have dropped.
        input_queue = LOCKSTEP_QUEUE if params.lockstep else 1
        odom_sub = rospy.Subscriber(params.odom_topic, Odometry, self.on_odom,
                                    queue_size=input_queue, tcp_nodelay=True)
        scan_subs = {topic: rospy.Subscriber(topic, LaserScan, self.on_scan, callback_args=topic,
                                             queue_size=input_queue, tcp_nodelay=True)
                     for topic in self.controller.scan_sources}
        self.frame_inputs = FrameInputs(
            lambda: odom_sub.get_num_connections() > 0,
            lambda topic: scan_subs[topic].get_num_connections() > 0,
            self.controller.scan_sources)
        rospy.Subscriber('detection', CanDetection, self.on_detection,
                         queue_size=input_queue, tcp_nodelay=True)
        if params.lockstep:
            rospy.Subscriber('frame_delivery', TimeReference, self.on_frame_delivery,
                             queue_size=input_queue, tcp_nodelay=True)
        self.diagnostics = NodeDiagnostics()
        self.diagnostics.add('control', self.control_health)
        self.diagnostics.add('camera pose', self.camera_pose_health)
        for monitor in self.monitors.values():
            self.diagnostics.add_input(monitor)
        rospy.on_shutdown(self.on_shutdown)
        self.timer = rospy.Timer(rospy.Duration(1.0 / params.rate), self.on_timer)
        self.diagnostics.start()

    def control_health(self):
        """The state, why the command is zero or limited, and the missing inputs."""
        now = rospy.get_time()
        with self.lock:
            return self.controller.health(now, self.why(now))

    def why(self, now):
        """Why the last command was zero or limited (under the lock). In lockstep the timer's
        zero of a stale detection bypasses the controller: the missing inputs say why."""
        if self.params.lockstep and self.stale_detection(now):
            return problems_text(self.controller.missing_inputs(now))
        return self.controller.why

    def stale_detection(self, now):
        """Whether a detection came and is stale now (in lockstep the timer then sends
        zero)."""
        return self.controller.detection_stale(now)

    def sensor_pose(self, frame_id):
        """The full pose (CameraPose: position, rotation) of a sensor frame in ~base_frame
        from TF, or None while TF does not have it."""
        return self.sensor_poses.pose(frame_id, rospy.get_time())

    def camera_pose_health(self):
        """ERROR while the newest detection of a red object had no camera pose in TF."""
        missing = self.camera_pose_missing
        if missing == '':
            return Health(OK, 'no red object seen yet')
        if missing is None:
            return Health(OK, 'from TF')
        hint = () if missing == UNSTAMPED else (('hint', PUBLISH_HINT),)
        return Health(ERROR, '%s: detections give the can\'s side, no range' % missing, hint)

    def on_camera_info(self, info):
        """The camera's intrinsics, for the floor footprint of each frame (:meth:`view_of`)."""
        try:
            intrinsics = intrinsics_from_k(info.width, info.height, info.K)
        except ValueError as error:
            self.monitors['camera_info'].received(rospy.get_time(), info.header.stamp.to_sec(),
                                                  str(error))
            rospy.logerr_throttle(5.0, 'can_stopper: bad camera_info: %s' % error)
            return
        self.monitors['camera_info'].received(rospy.get_time(), info.header.stamp.to_sec())
        with self.lock:
            self.intrinsics = intrinsics
            self.controller.observe_camera_info(rospy.get_time())

    def on_bumper(self, message):
        """The bumper: a new press stops the robot at once (this zero goes out before the next
        tick), the controller's bump recovery then backs it off."""
        now = rospy.get_time()
        self.monitors['bumper'].received(now)
        with self.lock:
            if self.shutting_down:
                return
            if self.controller.observe_bump(bool(message.data), now):
                self.publish_command(ZERO, rospy.Time.from_sec(now))
                rospy.logwarn('can_stopper: bumper pressed in %s: stopping, backing off %s'
                              % (self.controller.state.value, 'and keeping off the contact'))

    def on_enable(self, request):
        """Arm (true) or disarm (false); a disarm sends its zero at once."""
        with self.lock:
            now = rospy.get_time()
            if bool(request.data) != self.controller.enabled:
                self.frame_inputs.clear(now)
            message = self.controller.set_enabled(bool(request.data), now)
            if not request.data and not self.shutting_down:
                self.publish_command(ZERO, rospy.Time.from_sec(now))
        rospy.loginfo('can_stopper: %s' % message)
        self.publish_state(force=True)
        return SetBoolResponse(success=True, message=message)

    def view_of(self, pose):
        """The floor footprint (for the coverage grid) of a detection's camera at ``pose`` (its
        mount in TF when the detection came, so it follows a mount that changes, and a frame's
        coverage never depends on when its camera_info arrived); None without intrinsics or a
        pose (the last view stays)."""
        if pose is None or self.intrinsics is None:
            return None
        view = camera_view(pose, self.intrinsics, self.params.coverage_range,
                           self.params.can_height)
        if view != self.logged_view:
            self.logged_view = view
            rospy.loginfo('can_stopper: camera covers %.2f-%.2f m, +-%.1f deg'
                          % (view.near_m, view.far_m, math.degrees(view.half_fov_rad)))
        return view

    def on_odom(self, odom):
        self.monitors['odometry'].received(rospy.get_time(), odom.header.stamp.to_sec())
        pose = odom.pose.pose
        orientation = pose.orientation
        yaw = yaw_from_quaternion(orientation.x, orientation.y, orientation.z, orientation.w)
        if not all(math.isfinite(v) for v in (pose.position.x, pose.position.y, yaw)):
            rospy.logerr_throttle(5.0, 'can_stopper: ignoring odometry with a non-finite pose')
            return
        frame = odom.header.frame_id.lstrip('/')
        if frame and frame != self.odom_frame:
            rospy.logwarn_once('can_stopper: odometry is in %r, not in ~odom_frame %r: the map, '
                               'path and markers say %r' % (frame, self.odom_frame,
                                                            self.odom_frame))
        pose_2d = Pose2D(pose.position.x, pose.position.y, yaw)
        with self.lock:
            if not self.params.lockstep:
                self.controller.observe_pose(pose_2d, rospy.get_time(),
                                             odom.header.stamp.to_sec())
                return
            self.frame_inputs.pose(pose_2d, odom.header.stamp.to_sec())
            self.answer_frames()

    def on_scan(self, scan, topic):
        """A range scan of ``topic``: its rays into base_link through the sensor's pose in TF."""
        self.monitors[topic].received(rospy.get_time(), scan.header.stamp.to_sec())
        sensor = self.sensor_pose(scan.header.frame_id)
        if sensor is None:
            return
        ends, hits = scan_rays(scan.angle_min, scan.angle_increment, scan.ranges,
                               scan.range_min, scan.range_max)
        ends_3d = np.column_stack((ends, np.zeros(len(ends)))) @ sensor.rotation.T \
            + np.asarray(sensor.position)
        observation = (ends_3d[:, :2], hits, sensor.position[:2])
        with self.lock:
            if not self.params.lockstep:
                self.controller.observe_scan(topic, *observation, rospy.get_time(),
                                             scan.range_min, scan.header.stamp.to_sec())
                return
            self.frame_inputs.scan(topic, observation + (scan.range_min,),
                                   scan.header.stamp.to_sec(), scan.scan_time)
            self.answer_frames()

    def camera_pose(self, frame_id, pose):
        """The floor pose of camera ``frame_id`` at ``pose`` (from TF) in ~base_frame; None
        without a pose (its detections give the can's side, no range). Kept for the 'camera
        pose' diagnostics: None (from TF), else the missing transform ('' before any)."""
        if pose is None:
            self.camera_pose_missing = missing_transform(self.params.base_frame, frame_id)
            return None
        self.camera_pose_missing = None
        floor_pose = camera_floor_pose(pose)
        if frame_id not in self.camera_pose_logged:
            self.camera_pose_logged.add(frame_id)
            rospy.loginfo('can_stopper: camera %r at x=%.3f y=%.3f m, yaw %.4f rad in %s'
                          % (frame_id, floor_pose.x, floor_pose.y, floor_pose.yaw,
                             self.params.base_frame))
        return floor_pose

    def on_detection(self, detection):
        self.monitors['detection'].received(rospy.get_time(), detection.header.stamp.to_sec())
        problem = detection_problem(detection.found, detection.range, detection.bearing)
        if problem:
            rospy.logerr_throttle(2.0, 'can_stopper: ignoring the can in this detection: %s'
                                  % problem)
        # The controller decides from the confidence whether the red object is the can.
        pose = self.sensor_pose(detection.header.frame_id)
        camera = self.camera_pose(detection.header.frame_id, pose) if detection.found else None
        sighting = sighting_from_detection(detection.found, detection.range, detection.bearing,
                                           camera, self.params.robot_radius,
                                           self.params.can_radius, detection.confidence)
        view = self.view_of(pose)
        stamp_s = detection.header.stamp.to_sec()
        with self.lock:
            if not self.params.lockstep:
                self.observe(sighting, view, rospy.get_time(), stamp_s)
                return
            self.frame_inputs.detection((sighting, view), stamp_s)
            self.answer_frames()
        self.publish_state()

    def on_frame_delivery(self, delivery):
        """Lockstep: when the simulator published a frame (a late one answers from there)."""
        with self.lock:
            self.frame_inputs.delivery(delivery.time_ref.to_sec(),
                                       delivery.header.stamp.to_sec())
            self.answer_frames()

    def answer_frames(self):
        """Lockstep (under the lock): feed the controller every input in stamp order and
        answer each frame whose odometry and scan have arrived. The frame's sim time is the
        controller's clock; the simulator waits for the answer."""
        for kind, stamp_s, value in self.frame_inputs.ready():
            if kind == 'pose':
                self.controller.observe_pose(value, stamp_s)
            elif kind == 'scan':
                topic, (ends, hits, origin, range_min) = value
                self.controller.observe_scan(topic, ends, hits, origin, stamp_s, range_min)
            elif not self.shutting_down:
                stamp = rospy.Time.from_sec(stamp_s)
                self.guard.run(lambda: self.answer_frame(value, stamp_s, stamp),
                               lambda: self.publish_command(ZERO, stamp), stamp_s)

    def observe(self, sighting, view, now_s, stamp_s):
        """A detection (under the lock): its camera's view, then its sighting."""
        if view is not None:
            self.controller.set_camera_view(view)
        self.controller.observe(sighting, now_s, stamp_s)

    def answer_frame(self, detection, stamp_s, stamp):
        """Lockstep: the command for the frame of this detection ((sighting, view)), stamped
        like its image."""
        self.observe(*detection, stamp_s, stamp_s)
        self.publish_command(self.controller.command(stamp_s), stamp)

    def publish_command(self, command, stamp):
        """``command`` (linear m/s, angular rad/s) on /cmd_vel and, stamped, on cmd_vel_stamped;
        ValueError for a non-finite one."""
        message = twist(*require_finite(command))
        self.cmd_pub.publish(message)
        self.stamped_cmd_pub.publish(twist_stamped(message, stamp))

    def on_timer(self, _event):
        """One control tick; whatever fails in it, it ends in a published command (zero) and
        the timer lives on."""
        now = rospy.get_time()
        self.guard.run(lambda: self.tick(now), lambda: self.publish_zero(now), now)

    def publish_zero(self, now):
        """The zero of a failed tick, unless the shutdown zeros went out already."""
        with self.lock:
            if not self.shutting_down:
                self.publish_command(ZERO, rospy.Time.from_sec(now))

    def tick(self, now):
        """One control tick; publishes under the lock so no tick can follow the shutdown zeros.
        In lockstep only the zero of a stale detection or of a disarmed controller goes out
        (detections bring the commands)."""
        with self.lock:
            if self.shutting_down:
                return
            if not self.params.lockstep:
                self.publish_command(self.controller.command(now), rospy.Time.from_sec(now))
            elif self.stale_detection(now) or not self.controller.enabled:
                # Leaves the controller's command history alone: its timing stays the frames'.
                self.publish_command(ZERO, rospy.Time.from_sec(now))
            coverage = None
            if (self.controller.senses_obstacles
                    and abs(now - self.coverage_s) >= COVERAGE_PERIOD_S):
                self.coverage_s = now
                coverage = self.controller.map_layers()
            missing = self.controller.missing_inputs(now)
            state, why = self.controller.state.value, self.why(now)
            view = self.view(now)
        if coverage is not None:
            self.publish_coverage(coverage, now)
        if view is not None:
            self.publish_view(view, now)
        self.warn_missing(missing, state, why, now)
        self.publish_state()

    def warn_missing(self, missing, state, why, now):
        """Warn about each overdue input, at most once per input and period."""
        for item in missing:
            if item.overdue and self.missing_input_log.allow(item.name, now)[0]:
                rospy.logwarn('can_stopper: %s in %s; %s' % (
                    item.problem, state, 'command: %s' % why if why else
                    'command not limited by it'))

    def publish_coverage(self, layer, now):
        """The obstacle and coverage grid (values, cell size, origin) as an OccupancyGrid in
        ~odom_frame (100 obstacle, 0 floor the camera covered, -1 not covered)."""
        values, resolution_m, origin_m = layer
        self.coverage_pub.publish(occupancy_grid(
            values, resolution_m, (origin_m, origin_m), self.odom_frame,
            rospy.Time.from_sec(now)))

    def view(self, now):
        """What rviz is shown, under the lock, every VIEW_PERIOD_S while anyone subscribes:
        (obstacle grid layer or None, path or None, can estimate, robot xy, state)."""
        want_grid = self.obstacle_grid_pub.get_num_connections() > 0
        want_path = self.path_pub.get_num_connections() > 0
        want_markers = self.markers_pub.get_num_connections() > 0
        if not (want_grid or want_path or want_markers) or abs(now - self.view_s) < VIEW_PERIOD_S:
            return None
        self.view_s = now
        controller = self.controller
        grid = controller.map_layers(obstacles=True) if want_grid else None
        path = None if controller.path_xy is None else np.array(controller.path_xy)
        return (grid, path if want_path else False, controller.can_xy, controller.robot_xy,
                controller.state.value if want_markers else None)

    def publish_view(self, view, now):
        """~obstacle_grid, ~path and ~markers in ~odom_frame (those someone subscribes)."""
        grid, path, can_xy, robot_xy, state = view
        stamp = rospy.Time.from_sec(now)
        if grid is not None:
            values, resolution_m, origin_m = grid
            self.obstacle_grid_pub.publish(occupancy_grid(
                values, resolution_m, (origin_m, origin_m), self.odom_frame, stamp))
        if path is not False:
            self.path_pub.publish(path_msg(path, self.odom_frame, stamp))
        if state is not None:
            self.markers_pub.publish(controller_markers(
                can_xy, self.params.can_radius, self.params.can_height, robot_xy, state,
                self.odom_frame, stamp))

    def publish_state(self, force=False):
        """Publish the state when it changed (or always, with ``force``)."""
        state = self.controller.state.value
        if force or state != self.published_state:
            self.published_state = state
            self.state_pub.publish(String(data=state))
            rospy.loginfo('can_stopper: %s' % state)

    def on_reset(self, _request):
        with self.lock:
            reset_s = rospy.get_time()
            self.controller.reset(reset_s)
            self.frame_inputs.clear(reset_s)
        self.publish_state(force=True)
        return EmptyResponse()

    def on_shutdown(self):
        """Stop the ticks and send zero a few times (wall-clock spacing: sim time may be gone)."""
        with self.lock:
            self.shutting_down = True
        self.timer.shutdown()
        for _ in range(SHUTDOWN_ZERO_COUNT):
            self.publish_command(ZERO, rospy.Time.from_sec(rospy.get_time()))
            time.sleep(SHUTDOWN_ZERO_SPACING_S)


def main():
    rospy.init_node('can_stopper')
    try:
        params = read_params(PARAMS, rospy.get_param, rospy.logwarn)
    except UnsafeParamError as error:
        rospy.logfatal('can_stopper: %s' % error)
        sys.exit(1)
    CanStopperNode(controller_settings(params))
    rospy.spin()
