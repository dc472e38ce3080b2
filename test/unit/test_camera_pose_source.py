"""The one camera-pose rule (can_seeker.ros.camera_pose): refresh by the node's clock, keep the
last TF pose when a refresh fails; before TF gave a pose none, with an error naming the missing
transform and how to publish it (an offline tool's fallback pose instead)."""
import tf2_ros
from geometry_msgs.msg import Transform

from can_seeker.camera_geometry import camera_pose_from_transform
from can_seeker.ros.camera_pose import PUBLISH_HINT, CameraPoseSource, missing_transform

FALLBACK = camera_pose_from_transform((0.1, 0.0, 0.2), (0.0, 0.0, 0.0, 1.0))


class FakeTF:
    """lookup(base, frame): a transform at height ``z``, or LookupException while ``up`` is
    False; counts the lookups."""

    def __init__(self):
        self.up = True
        self.z = 0.25
        self.calls = []

    def __call__(self, base, frame):
        self.calls.append((base, frame))
        if not self.up:
            raise tf2_ros.LookupException('no %s' % frame)
        transform = Transform()
        transform.translation.z = self.z
        transform.rotation.w = 1.0
        return transform


def test_looks_up_base_from_frame_and_refreshes_once_a_period():
    tf = FakeTF()
    source = CameraPoseSource(tf, 'robot1/base_link', FALLBACK, refresh_s=1.0)
    assert source.pose('/robot1/camera_optical_frame', 10.0).height_m == 0.25
    assert tf.calls == [('robot1/base_link', 'robot1/camera_optical_frame')]
    tf.z = 0.3
    assert source.pose('robot1/camera_optical_frame', 10.9).height_m == 0.25
    assert len(tf.calls) == 1
    assert source.pose('robot1/camera_optical_frame', 11.0).height_m == 0.3
    assert source.age_s('robot1/camera_optical_frame', 11.5) == 0.5


def test_a_clock_that_jumps_back_counts_as_elapsed():
    tf = FakeTF()
    source = CameraPoseSource(tf, 'base_link', refresh_s=1.0)
    source.pose('camera', 50.0)
    source.pose('camera', 2.0)  # a simulator reset
    assert len(tf.calls) == 2


def test_fallback_until_tf_gives_a_pose_then_the_last_tf_pose_is_kept():
    tf = FakeTF()
    tf.up = False
    warnings = []
    source = CameraPoseSource(tf, 'base_link', FALLBACK, warnings.append, refresh_s=1.0)
    assert source.pose('camera', 0.0) is FALLBACK
    assert not source.from_tf_yet('camera') and source.age_s('camera', 0.0) is None
    tf.up = True
    pose = source.pose('camera', 0.1)
    assert pose.height_m == 0.25 and source.from_tf_yet('camera')
    tf.up = False
    assert source.pose('camera', 5.0) is pose
    assert source.age_s('camera', 5.0) == 4.9
    assert 'given camera mount' in warnings[0] and 'keeping the pose' in warnings[-1]


def test_without_a_fallback_there_is_no_pose_until_tf_has_one_and_an_error_says_so():
    tf = FakeTF()
    tf.up = False
    errors, warnings = [], []
    source = CameraPoseSource(tf, 'robot1/base_link', warn=warnings.append, error=errors.append,
                              without='no scan')
    assert source.pose('/robot1/camera_optical_frame', 0.0) is None
    assert warnings == [] and len(errors) == 1
    assert errors[0].startswith('no TF robot1/base_link <- robot1/camera_optical_frame (')
    assert 'no scan' in errors[0] and errors[0].endswith(PUBLISH_HINT)
    assert PUBLISH_HINT.startswith('publish the camera mount in TF: roslaunch can_seeker '
                                   'robot_state.launch')
    assert 'rosrun tf2_ros' not in PUBLISH_HINT  # Debian's ROS packages ship no such binary
    tf.up = True
    assert source.pose('robot1/camera_optical_frame', 0.1).height_m == 0.25
    assert len(errors) == 1


class StrictTF(FakeTF):
    """tf2 itself refuses an empty frame name."""

    def __call__(self, base, frame):
        if not frame:
            raise tf2_ros.InvalidArgumentException('frame_ids cannot be empty')
        return super().__call__(base, frame)


def test_an_unstamped_image_asks_for_the_drivers_frame_id_not_for_a_transform():
    errors = []
    source = CameraPoseSource(StrictTF(), 'base_footprint', error=errors.append,
                              without='range and bearing are NaN')
    assert source.pose('', 0.0) is None
    assert len(errors) == 1
    assert 'empty frame_id' in errors[0] and 'camera_frame_id' in errors[0]
    assert PUBLISH_HINT not in errors[0]
    assert errors[0].endswith('range and bearing are NaN')
    assert missing_transform('base_footprint', '') == missing_transform('base_link', '/')
    assert missing_transform('base_link', 'camera') == 'no TF base_link <- camera'
