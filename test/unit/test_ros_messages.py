"""The message builders of can_seeker.ros.messages (message classes only, no master)."""
import math

import numpy as np
import pytest
import rospy
from visualization_msgs.msg import Marker

from can_seeker.ros import messages


def test_occupancy_grid_is_row_major_from_the_origin_cell():
    values = np.array([[0, 100, -1], [100, 0, 0]], np.int8)  # 2 rows (y) x 3 columns (x)
    grid = messages.occupancy_grid(values, 0.1, (-1.5, -1.0), 'robot1/odom', rospy.Time(3))
    assert grid.header.frame_id == 'robot1/odom' and grid.header.stamp == rospy.Time(3)
    assert (grid.info.width, grid.info.height) == (3, 2)
    assert grid.info.resolution == pytest.approx(0.1)
    assert (grid.info.origin.position.x, grid.info.origin.position.y) == (-1.5, -1.0)
    assert grid.info.origin.orientation.w == 1.0
    assert list(grid.data) == [0, 100, -1, 100, 0, 0]


def test_path_poses_follow_the_points_and_head_along_the_path():
    path = messages.path_msg(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]), 'odom',
                             rospy.Time(2))
    assert path.header.frame_id == 'odom'
    assert [(p.pose.position.x, p.pose.position.y) for p in path.poses] == [
        (0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]
    yaws = [2.0 * math.atan2(p.pose.orientation.z, p.pose.orientation.w) for p in path.poses]
    assert yaws == pytest.approx([0.0, math.pi / 2, math.pi / 2])
    assert all(p.header.frame_id == 'odom' for p in path.poses)


@pytest.mark.parametrize('path_xy', [None, np.zeros((0, 2))])
def test_no_path_is_an_empty_path(path_xy):
    path = messages.path_msg(path_xy, 'odom', rospy.Time(1))
    assert path.poses == [] and path.header.frame_id == 'odom'


def test_markers_show_the_can_as_a_cylinder_and_the_state_above_the_robot():
    markers = messages.controller_markers((1.2, -0.3), 0.033, 0.122, (0.5, 0.25), 'APPROACH',
                                          'robot1/odom', rospy.Time(5)).markers
    can, state = markers
    assert (can.ns, can.type, can.action) == ('can', Marker.CYLINDER, Marker.ADD)
    assert (can.pose.position.x, can.pose.position.y) == (1.2, -0.3)
    assert can.pose.position.z == pytest.approx(0.061)
    assert (can.scale.x, can.scale.y, can.scale.z) == pytest.approx((0.066, 0.066, 0.122))
    assert can.color.a > 0.0
    assert (state.ns, state.type, state.action, state.text) == (
        'state', Marker.TEXT_VIEW_FACING, Marker.ADD, 'APPROACH')
    assert (state.pose.position.x, state.pose.position.y) == (0.5, 0.25)
    assert state.pose.position.z > 0.122 and state.scale.z > 0.0
    assert {m.header.frame_id for m in markers} == {'robot1/odom'}
    assert all(m.pose.orientation.w == 1.0 for m in markers)


def test_markers_without_a_can_or_a_pose_are_deleted():
    can, state = messages.controller_markers(None, 0.033, 0.122, None, 'SEARCH', 'odom',
                                             rospy.Time(1)).markers
    assert (can.ns, can.action) == ('can', Marker.DELETE)
    assert (state.ns, state.action, state.text) == ('state', Marker.DELETE, 'SEARCH')


def test_odometry_and_transform_carry_their_frames():
    odom = messages.odometry(rospy.Time(1), 'r/odom', 'r/base_link', (1.0, 2.0, 0.0),
                             (0.0, 0.0, 0.0, 1.0), (0.1, 0.0, 0.0), (0.0, 0.0, 0.2))
    assert (odom.header.frame_id, odom.child_frame_id) == ('r/odom', 'r/base_link')
    assert (odom.pose.pose.position.x, odom.twist.twist.angular.z) == (1.0, 0.2)
    transform = messages.transform_stamped(rospy.Time(1), 'r/base_link', 'r/camera_link',
                                           (0.12, 0.0, 0.25), (0.0, 0.2, 0.0, 0.98))
    assert (transform.header.frame_id, transform.child_frame_id) == ('r/base_link',
                                                                     'r/camera_link')
    assert transform.transform.translation.z == 0.25


def test_mount_transforms_chain_base_camera_and_optical_frames():
    from can_seeker.camera_mount import CameraMount
    mount = CameraMount(0.3, 20.0, 0.1)
    base_camera, camera_optical = messages.mount_transforms(rospy.Time(2), mount, 'r/base',
                                                            'r/cam', 'r/optical')
    assert [(t.header.frame_id, t.child_frame_id) for t in (base_camera, camera_optical)] == [
        ('r/base', 'r/cam'), ('r/cam', 'r/optical')]
    assert base_camera.header.stamp == rospy.Time(2)
    assert base_camera.transform.translation.x == 0.1
    assert base_camera.transform.translation.z == 0.3
    assert (base_camera.transform.rotation.y, base_camera.transform.rotation.w) == \
        mount.rotation_xyzw[1::2]
    rotation = camera_optical.transform.rotation
    assert (rotation.x, rotation.y, rotation.z, rotation.w) == (-0.5, 0.5, -0.5, 0.5)


def test_twist_stamped_keeps_the_command():
    stamped = messages.twist_stamped(messages.twist(0.3, -0.5), rospy.Time(4))
    assert (stamped.twist.linear.x, stamped.twist.angular.z) == (0.3, -0.5)
    assert stamped.header.stamp == rospy.Time(4)
