"""Reading a URDF's joints back, shared by the robot-model and world-URDF tests."""
import math

import numpy as np


def joint_origin(robot, name):
    """(xyz, rpy) of joint ``name``'s origin in the parsed URDF ``robot``."""
    origin = robot.find("joint[@name='%s']/origin" % name)
    return ([float(value) for value in origin.get('xyz').split()],
            [float(value) for value in origin.get('rpy').split()])


def rpy_matrix(roll, pitch, yaw):
    """URDF fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    return (np.array(((cy, -sy, 0), (sy, cy, 0), (0, 0, 1)))
            @ np.array(((cp, 0, sp), (0, 1, 0), (-sp, 0, cp)))
            @ np.array(((1, 0, 0), (0, cr, -sr), (0, sr, cr))))
