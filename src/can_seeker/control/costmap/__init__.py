"""The controller's world model as costmap layers over one odom-frame grid, behind
:class:`can_seeker.control.costmap.world_map.WorldMap` (pure numpy, no ROS)."""
