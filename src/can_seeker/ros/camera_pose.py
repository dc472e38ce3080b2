"""The one camera-pose source of every node and tool: a sensor frame's pose in a base frame from
TF, with one refresh rule.

The rule (:class:`CameraPoseSource`):

- the pose of ``frame_id`` in ``base_frame`` is looked up in TF (latest transform) for every
  frame (:data:`REFRESH_S` 0; a larger one reuses a pose for that long of the node's clock, a
  clock that jumps back counting as elapsed time too): a lookup costs a few microseconds, and
  a mount that changes (a simulator drawing one per world, a pan-tilt unit) is followed at
  once;
- a failed refresh keeps the last pose TF gave (its age grows: :meth:`CameraPoseSource.age_s`);
- until TF has given a pose at all there is none, and an error through ``error`` names the
  missing transform, what the node does without it (``without``) and how to publish it
  (:data:`PUBLISH_HINT`); an offline tool may give a ``fallback`` pose for that time instead;
- for an image (``require_optical``), a frame TF gives that is no optical frame (z forward,
  x right, y down: :func:`can_seeker.camera_geometry.optical_frame_problem`, e.g. images
  stamped in camera_link) gives no pose at all, and an error through ``error``: every range
  from it would be wrong.

A failed refresh is warned about through ``warn``, a missing transform and a wrong frame
through ``error`` (both throttled by the caller's logger).
"""
from typing import Callable, Dict, Optional, Tuple

import rospy
import tf2_ros

from can_seeker.camera_geometry import (CameraPose, camera_pose_from_transform,
                                        optical_frame_problem)

REFRESH_S = 0.0
"""A pose from TF is looked up again after this long (s, the node's clock): every frame."""
WARN_PERIOD_S = 5.0
PUBLISH_HINT = ('publish the camera mount in TF: roslaunch can_seeker robot_state.launch with the '
                'robot\'s robot_description (robot_description.launch makes one from '
                'camera_height and camera_pitch_deg, or robot:=PROFILE), or a '
                'static_transform_publisher where tf2_ros ships it (ROS from ros.org)')
"""How to give a node the transform it lacks."""


UNSTAMPED = ('an empty frame_id, which TF cannot place: set the driver\'s frame id parameter '
             '(camera_frame_id for raspicam_node and usb_cam, frame_id for most lidar '
             'drivers) to the sensor\'s frame in TF')
"""What a message with an empty header.frame_id lacks (raspicam_node's default)."""


def missing_transform(base_frame: str, frame_id: str) -> str:
    """The words naming a transform TF lacks, as the nodes' errors and diagnostics say it (a
    message without a frame_id lacks the frame, not the transform: :data:`UNSTAMPED`)."""
    if not frame_id.lstrip('/'):
        return UNSTAMPED
    return 'no TF %s <- %s' % (base_frame, frame_id.lstrip('/'))


def pose_from_transform(transform) -> CameraPose:
    """The CameraPose of a geometry_msgs/Transform (base <- frame)."""
    translation, rotation = transform.translation, transform.rotation
    return camera_pose_from_transform((translation.x, translation.y, translation.z),
                                      (rotation.x, rotation.y, rotation.z, rotation.w))


class CameraPoseSource:
    """Poses of sensor frames in ``base_frame``: ``lookup(base_frame, frame_id)`` returns a
    geometry_msgs/Transform or raises (tf2_ros.TransformException, ValueError); see the module
    for the refresh rule; ``without`` says what the caller does without a pose."""

    def __init__(self, lookup: Callable, base_frame: str,
                 fallback: Optional[CameraPose] = None,
                 warn: Optional[Callable[[str], None]] = None, refresh_s: float = REFRESH_S,
                 require_optical: bool = False,
                 error: Optional[Callable[[str], None]] = None,
                 without: str = 'no pose'):
        self.lookup = lookup
        self.base_frame = base_frame
        self.fallback = fallback
        self.warn = warn or (lambda message: None)
        self.error = error or self.warn
        self.refresh_s = refresh_s
        self.require_optical = require_optical
        self.without = without
        self.poses: Dict[str, Tuple[CameraPose, float]] = {}
        self.problems: Dict[str, str] = {}

    @classmethod
    def from_tf(cls, buffer, base_frame: str, name: str = 'node',
                refresh_s: float = REFRESH_S, require_optical: bool = False,
                without: str = 'no pose') -> 'CameraPoseSource':
        """A source on a tf2_ros.Buffer or a :class:`can_seeker.ros.sensor_tf.SensorTf`
        (latest transforms), warning (and reporting a missing transform or a wrong frame as an
        error) through rospy as ``name``."""
        return cls(lambda target, source: buffer.lookup_transform(
                       target, source, rospy.Time(0)).transform,
                   base_frame, None,
                   lambda message: rospy.logwarn_throttle(WARN_PERIOD_S,
                                                          '%s: %s' % (name, message)),
                   refresh_s, require_optical,
                   lambda message: rospy.logerr_throttle(WARN_PERIOD_S,
                                                         '%s: %s' % (name, message)),
                   without)

    @classmethod
    def from_buffer_core(cls, core, base_frame: str, fallback: Optional[CameraPose] = None,
                         refresh_s: float = REFRESH_S,
                         require_optical: bool = False) -> 'CameraPoseSource':
        """A source on a tf2_ros.BufferCore filled by hand (a bag's TF), silent (a wrong frame
        is kept in :attr:`problems`), with the ``fallback`` pose until the bag's TF gives
        one."""
        return cls(lambda target, source: core.lookup_transform_core(
                       target, source, rospy.Time(0)).transform,
                   base_frame, fallback, None, refresh_s, require_optical)

    def pose(self, frame_id: str, now_s: float) -> Optional[CameraPose]:
        """The pose of ``frame_id`` (a leading '/' is ignored) in the base frame at ``now_s``
        (s, the node's clock): from TF, the last one TF gave, or the fallback; None when there
        is none (the error names the missing transform), or TF gives one that is no optical
        frame while ``require_optical`` (the reason is in :attr:`problems`)."""
        frame_id = frame_id.lstrip('/')
        cached = self.poses.get(frame_id)
        if cached is not None and abs(now_s - cached[1]) < self.refresh_s:
            return cached[0]
        try:
            pose = pose_from_transform(self.lookup(self.base_frame, frame_id))
        except (tf2_ros.TransformException, ValueError) as error:
            if cached is not None:
                self.warn('no TF %s <- %s now (%s); keeping the pose TF gave %.1f s ago'
                          % (self.base_frame, frame_id, error, now_s - cached[1]))
                return cached[0]
            if self.fallback is not None:
                self.warn('%s yet (%s); using the given camera mount'
                          % (missing_transform(self.base_frame, frame_id), error))
                return self.fallback
            if not frame_id:
                self.error('%s: %s' % (UNSTAMPED, self.without))
            else:
                self.error('%s (%s): %s; %s' % (missing_transform(self.base_frame, frame_id),
                                                error, self.without, PUBLISH_HINT))
            return None
        if self.require_optical:
            problem = optical_frame_problem(pose, frame_id)
            if problem is not None:
                self.problems[frame_id] = problem
                self.poses.pop(frame_id, None)
                self.error('%s: no range, bearing or scan from it' % problem)
                return None
            self.problems.pop(frame_id, None)
        self.poses[frame_id] = (pose, now_s)
        return pose

    def from_tf_yet(self, frame_id: str) -> bool:
        """Whether TF has given the pose of ``frame_id`` (not the fallback)."""
        return frame_id.lstrip('/') in self.poses

    def age_s(self, frame_id: str, now_s: float) -> Optional[float]:
        """How old the pose TF last gave for ``frame_id`` is (s), None before TF gave one."""
        cached = self.poses.get(frame_id.lstrip('/'))
        return None if cached is None else now_s - cached[1]

    def clear(self) -> None:
        """Forget the poses TF gave (the next :meth:`pose` looks them up again)."""
        self.poses.clear()
