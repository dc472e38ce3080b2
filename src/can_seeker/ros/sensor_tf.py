"""TF for a node that looks up its sensors' mounts: /tf_static always, /tf only while a lookup
needs it (:class:`can_seeker.tf_demand.TfDemand`).

With its camera and lidar on fixed joints (/tf_static) a node receives none of the /tf
messages (the odometry transform at the simulator's state rate), each of which costs a rospy
thread's wake-up and a deserialisation. The rule:

- a lookup is answered from /tf_static alone when the whole chain is there: the transform the
  whole tree gives, and a new /tf_static message (a new mount) counts at once;
- otherwise (a camera on a moving joint, a mount whose /tf_static has not arrived) from a
  buffer of /tf and /tf_static, as tf2_ros.TransformListener keeps;
- /tf is received from the start and while the last lookup of any frame pair needed it; then
  it is unsubscribed, and subscribed again (a buffer of its own: no stale transforms) when a
  lookup needs it. The lookup that subscribes it again finds no /tf yet: the caller keeps the
  last pose it had (:mod:`can_seeker.ros.camera_pose`).
- a clock that jumps back clears the /tf transforms, as tf2_ros.TransformListener does
  (static ones hold at any time and stay).
"""
import threading
from typing import Callable, Dict, Optional, Tuple

import rospy
import tf2_ros
from tf2_msgs.msg import TFMessage

from can_seeker.tf_demand import TfDemand


def rospy_subscribe(topic: str, callback: Callable):
    """A TFMessage subscriber as tf2_ros.TransformListener makes them."""
    return rospy.Subscriber(topic, TFMessage, callback, queue_size=None, buff_size=65536)


class SensorTf:
    """Lookups of sensor mounts (``lookup_transform`` as tf2_ros.Buffer's); ``subscribe(topic,
    callback)`` returns a subscriber with ``unregister()``, ``now()`` the node's clock (a
    rospy.Time) for the jump-back check."""

    def __init__(self, subscribe: Callable = rospy_subscribe, now: Callable = rospy.Time.now,
                 warn: Optional[Callable[[str], None]] = None):
        self.subscribe = subscribe
        self.now = now
        self.warn = warn or (lambda message: None)
        self.lock = threading.Lock()
        self.demand = TfDemand()
        self.static = tf2_ros.BufferCore()
        self.static_transforms: Dict[str, Tuple[object, str]] = {}
        self.dynamic: Optional[tf2_ros.BufferCore] = None
        self.tf_sub = None
        self.last_update = now()
        with self.lock:
            self._follow_demand()
        self.static_sub = subscribe('/tf_static', self.on_tf_static)

    @property
    def receives_tf(self) -> bool:
        """Whether /tf is subscribed now."""
        return self.tf_sub is not None

    def lookup_transform(self, target: str, source: str, time) -> object:
        """geometry_msgs/TransformStamped target <- source at ``time`` (rospy.Time(0): the
        latest); raises tf2_ros.TransformException."""
        try:
            transform = self.static.lookup_transform_core(target, source, time)
            from_static = True
        except tf2_ros.TransformException:
            from_static = False
        with self.lock:
            self.demand.looked_up((target, source), from_static)
            self._follow_demand()
            dynamic = self.dynamic
        if from_static:
            return transform
        return dynamic.lookup_transform_core(target, source, time)

    def on_tf(self, message) -> None:
        self._check_for_reset()
        dynamic, authority = self.dynamic, _authority(message)
        if dynamic is None:
            return
        for transform in message.transforms:
            dynamic.set_transform(transform, authority)

    def on_tf_static(self, message) -> None:
        self._check_for_reset()
        authority = _authority(message)
        with self.lock:
            for transform in message.transforms:
                self.static_transforms[transform.child_frame_id] = (transform, authority)
                self.static.set_transform_static(transform, authority)
                if self.dynamic is not None:
                    self.dynamic.set_transform_static(transform, authority)

    def _follow_demand(self) -> None:
        """(Under the lock) subscribe /tf or unsubscribe it as the lookups need."""
        if self.demand.needs_tf and self.tf_sub is None:
            dynamic = tf2_ros.BufferCore()
            for transform, authority in self.static_transforms.values():
                dynamic.set_transform_static(transform, authority)
            self.dynamic = dynamic
            self.tf_sub = self.subscribe('/tf', self.on_tf)
        elif not self.demand.needs_tf and self.tf_sub is not None:
            self.tf_sub.unregister()
            self.tf_sub, self.dynamic = None, None

    def _check_for_reset(self) -> None:
        with self.lock:
            now = self.now()
            if now < self.last_update:
                self.warn('detected a jump back in time of %fs: clearing the /tf transforms'
                          % (self.last_update - now).to_sec())
                if self.dynamic is not None:
                    self.dynamic.clear()
            self.last_update = now


def _authority(message) -> str:
    header = getattr(message, '_connection_header', None) or {}
    return header.get('callerid', 'default_authority')
