"""Sensor mounts from TF with /tf only while a lookup needs it (can_seeker.ros.sensor_tf), on
tf2's own buffers: a fixed mount, a camera on a moving joint, a TF that arrives late, a mount
that changes; and the conversion cache of camera_info (can_seeker.tf_demand)."""
import pytest
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

from can_seeker.ros.camera_pose import CameraPoseSource
from can_seeker.ros.sensor_tf import SensorTf
from can_seeker.tf_demand import TfDemand

LATEST = rospy.Time(0)


class Topics:
    """subscribe(topic, callback) of a node: which topics it receives now, and delivery."""

    def __init__(self):
        self.callbacks = {}
        self.subscriptions = []

    def subscribe(self, topic, callback):
        topics = self

        class Subscriber:
            def unregister(self):
                del topics.callbacks[topic]

        assert topic not in self.callbacks
        self.callbacks[topic] = callback
        self.subscriptions.append(topic)
        return Subscriber()

    def deliver(self, topic, *transforms):
        """Deliver a TFMessage when the node receives ``topic``; whether it did."""
        if topic not in self.callbacks:
            return False
        self.callbacks[topic](TFMessage(transforms=list(transforms)))
        return True


def transform(parent, child, x, stamp_s=0.0):
    message = TransformStamped()
    message.header.frame_id, message.child_frame_id = parent, child
    message.header.stamp = rospy.Time.from_sec(stamp_s)
    message.transform.translation.x = x
    message.transform.rotation.w = 1.0
    return message


class Clock:
    def __init__(self):
        self.s = 10.0

    def __call__(self):
        return rospy.Time.from_sec(self.s)


def sensor_tf():
    topics, clock = Topics(), Clock()
    return SensorTf(topics.subscribe, clock), topics, clock


def x_of(tf, target, source):
    return tf.lookup_transform(target, source, LATEST).transform.translation.x


def test_a_fixed_mount_needs_tf_only_until_it_resolved_from_tf_static():
    tf, topics, _ = sensor_tf()
    assert tf.receives_tf and '/tf_static' in topics.callbacks
    topics.deliver('/tf', transform('odom', 'base_link', 1.0, 1.0))
    topics.deliver('/tf_static', transform('base_link', 'camera_link', 0.1),
                   transform('camera_link', 'camera_optical_frame', 0.02))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.12)
    assert not tf.receives_tf
    assert not topics.deliver('/tf', transform('odom', 'base_link', 2.0, 2.0))
    # A new mount (a new /tf_static message) counts at once.
    topics.deliver('/tf_static', transform('base_link', 'camera_link', 0.2),
                   transform('camera_link', 'camera_optical_frame', 0.02))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.22)
    assert not tf.receives_tf


def test_a_camera_on_a_moving_joint_keeps_tf_and_follows_it():
    tf, topics, _ = sensor_tf()
    topics.deliver('/tf_static', transform('pan_link', 'camera_optical_frame', 0.05),
                   transform('base_link', 'base_scan', 0.0))
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.1, 1.0))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.15)
    assert x_of(tf, 'base_link', 'base_scan') == 0.0  # the lidar is fixed, the camera is not
    assert tf.receives_tf
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.3, 2.0))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.35)
    assert tf.receives_tf


def test_a_tf_that_arrives_late():
    tf, topics, _ = sensor_tf()
    with pytest.raises(tf2_ros.TransformException):
        tf.lookup_transform('base_link', 'camera_optical_frame', LATEST)
    assert tf.receives_tf
    topics.deliver('/tf_static', transform('base_link', 'camera_optical_frame', 0.1))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.1)
    assert not tf.receives_tf


def test_tf_is_received_again_with_a_buffer_of_its_own_when_a_lookup_needs_it():
    tf, topics, _ = sensor_tf()
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.1, 1.0))
    topics.deliver('/tf_static', transform('base_link', 'camera_optical_frame', 0.1),
                   transform('pan_link', 'pan_camera', 0.05))
    x_of(tf, 'base_link', 'camera_optical_frame')
    assert not tf.receives_tf
    # The pan joint's old transform is gone with the old buffer: no pose until /tf brings one.
    with pytest.raises(tf2_ros.TransformException):
        tf.lookup_transform('base_link', 'pan_camera', LATEST)
    assert tf.receives_tf and topics.subscriptions.count('/tf') == 2
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.4, 3.0))
    assert x_of(tf, 'base_link', 'pan_camera') == pytest.approx(0.45)
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.1)
    assert tf.receives_tf


def test_a_clock_jumping_back_clears_the_tf_transforms_not_the_static_ones():
    tf, topics, clock = sensor_tf()
    topics.deliver('/tf_static', transform('pan_link', 'camera_optical_frame', 0.05))
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.1, 1.0))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.15)
    clock.s = 1.0
    topics.deliver('/tf', transform('odom', 'base_link', 0.0, 0.5))
    with pytest.raises(tf2_ros.TransformException):
        tf.lookup_transform('base_link', 'camera_optical_frame', LATEST)
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.2, 0.6))
    assert x_of(tf, 'base_link', 'camera_optical_frame') == pytest.approx(0.25)


def test_camera_pose_source_follows_a_moving_joint_through_sensor_tf():
    tf, topics, _ = sensor_tf()
    poses = CameraPoseSource.from_tf(tf, 'base_link')
    topics.deliver('/tf_static', transform('pan_link', 'camera_optical_frame', 0.05))
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.1, 1.0))
    assert poses.pose('camera_optical_frame', 1.0).position[0] == pytest.approx(0.15)
    topics.deliver('/tf', transform('base_link', 'pan_link', 0.2, 2.0))
    assert poses.pose('camera_optical_frame', 2.0).position[0] == pytest.approx(0.25)


def test_tf_demand():
    demand = TfDemand()
    assert demand.needs_tf  # nothing looked up yet
    demand.looked_up(('base_link', 'camera'), False)
    assert demand.needs_tf
    demand.looked_up(('base_link', 'lidar'), True)
    assert demand.needs_tf  # the camera still needs /tf
    demand.looked_up(('base_link', 'camera'), True)
    assert not demand.needs_tf

