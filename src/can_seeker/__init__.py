"""can_seeker: find a red can with one camera, drive to it and stop just in front of it.

Pure modules (no rospy) hold all logic; the nodes in ``can_seeker.nodes`` are thin ROS glue.
"""
