"""The TF frames of the robot: each one a node parameter, declared here once with its default.

Every node that names a frame reads it from its own ``~param`` of these declarations, so a robot
whose frames are called otherwise (or carry a prefix, as ``robot1/base_link`` under
``<group ns="robot1">``: demo.launch's ``frame_prefix``) only sets parameters.
"""
from can_seeker.params import Param

BASE_FRAME = Param('base_frame', 'base_link', 'frame of the robot base, on the floor with z up '
                   '(REP-103); the camera pose is looked up in TF in it')
ODOM_FRAME = Param('odom_frame', 'odom', 'odometry frame: the robot\'s pose estimate, the '
                   'obstacle map and the planned path are in it')
CAMERA_FRAME = Param('camera_frame', 'camera_link', 'frame of the camera body (x forward, '
                     'z up), child of ~base_frame')
OPTICAL_FRAME = Param('optical_frame', 'camera_optical_frame', 'optical frame of the camera '
                      '(z forward, x right, y down), child of ~camera_frame; the images\' '
                      'frame_id')
LIDAR_FRAME = Param('lidar_frame', 'base_scan', 'frame of the lidar and its /scan, child of '
                    '~base_frame')
WORLD_FRAME = Param('world_frame', 'world', 'the simulator\'s fixed frame of the ground truth '
                    '(odom coincides with it at the start and after every reset)')

SIM_FRAME_PARAMS = (BASE_FRAME, ODOM_FRAME, CAMERA_FRAME, OPTICAL_FRAME, LIDAR_FRAME,
                    WORLD_FRAME)
"""The frames the simulator publishes."""

