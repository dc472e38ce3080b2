"""can_seeker: find a red can with one camera, drive to it and stop just in front of it.

Pure modules (no rospy) hold all logic; the nodes in ``can_seeker.nodes`` are thin ROS glue.
"""
from pkgutil import extend_path

# The package is split between the source tree and catkin's devel space (generated messages);
# a process that finds the source tree first on sys.path (a spawned worker inherits the sys.path
# catkin's devel __init__ put it on) still sees both halves.
__path__ = extend_path(__path__, __name__)
