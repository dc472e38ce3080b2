"""The controller's internal heuristics: fixed values, not parameters.

These are what the control law, the can tracker, the map and the planner need to work, and
nothing a robot owner or a room calls for: a robot's own figures (size, speed and acceleration
limits, frames, topics, sensors) are the can_stopper parameters
(:data:`can_seeker.control.controller.PARAMS`). :func:`controller_settings` joins
both into the one settings object every part of the controller reads.
"""
from types import SimpleNamespace

from can_seeker.can_size import CAN_DIAMETER_M, CAN_HEIGHT_M

CAN_RADIUS_M = CAN_DIAMETER_M / 2.0
"""Radius of the can: the near surface a detection ranges lies this far in front of the can's
centre (CAN_HEIGHT_M: the floor nearer than a can's top shows in the camera's view)."""
MIN_CONFIDENCE = 0.5
"""Act only on detections whose confidence that the red object is the can is at least this
(image_converter's size and shape checks give a can at its range about 1, other red objects
less)."""
TRACK_CONFIDENCE = 0.2
"""While approaching or stopped, a detection within TRACK_GATE_M of where the can was ranged
counts as the can down to this confidence: close up, a label's lettering changes the
silhouette from frame to frame."""
TRACK_GATE_M = 0.3
"""How far from the tracked can a weaker detection may place it (beyond: another object)."""
DISTANCE_TOLERANCE_M = 0.01
"""STOPPED once the gap is within this of stop_distance and the robot is at rest; the approach
aims at the middle half of the band, so the last step does not overshoot it."""
BEARING_TOLERANCE_DEG = 1.5
"""STOPPED only with the can within this bearing of straight ahead; turning aims at half of
it."""
REAPPROACH_DISTANCE_M = 0.05
"""STOPPED drives again when the gap differs from stop_distance by more than this: five times
DISTANCE_TOLERANCE_M, a hysteresis band, so a robot stopped at the edge of the stop band does
not start again, and a can that moved brings it back."""
REAPPROACH_BEARING_DEG = 6.0
"""STOPPED turns again when the can's bearing exceeds this."""
MIN_LINEAR_MPS = 0.03
"""Slowest approach speed outside the dead-band, so the robot really arrives."""
MIN_ANGULAR_RADPS = 0.08
"""Slowest corrective turn rate outside the dead-band, so small bearing errors close."""
LINEAR_GAIN_PER_S = 1.5
"""Approach speed per metre of gap error (m/s per m)."""
ANGULAR_GAIN_PER_S = 2.0
"""Turn rate per radian of bearing error (rad/s per rad)."""
TURN_IN_PLACE_DEG = 25.0
"""The robot drives forward only while the bearing (of the can in APPROACH, of the lookahead
point on grid paths) is within this, at full speed when it is zero."""
SEARCH_ANGULAR_RADPS = 0.8
"""Turn rate in SEARCH, LOST and WANDER, and of the turns toward unseen floor (max_angular
still limits it)."""
LOST_TIMEOUT_S = 5.0
"""LOST becomes SEARCH after this long without the can and without getting nearer the can's
last place."""
VANISH_TIMEOUT_S = 1.5
"""STOPPED becomes LOST when the can has not been seen with a range for this long; APPROACH
stops only where the can was seen with a range this recently, or where it is below the
camera's view."""
GRID_RESOLUTION_M = 0.1
"""Cell size of the odom-frame obstacle and coverage grid."""
MAP_SIZE_M = 20.0
"""Side of the square grid about the odom origin: a room and more."""
COVERAGE_RANGE_M = 2.5
"""Farthest floor the camera counts as covered, where it still finds the can."""
PLAN_MARGIN_M = 0.15
"""Clearance kept from obstacles on planned paths, beyond robot_radius; where no path keeps it
(a narrow passage), paths keep the safety layer's margin."""
EXPLORE_LINEAR_MPS = 0.3
"""Cruise speed while exploring, on paths and wandering, unless max_linear is lower (then
max_linear)."""
EXPLORE_TURN_COST_M_PER_RAD = 0.3
"""Exploration prefers goals ahead: metres of path one radian of turning is worth."""
REPLAN_PERIOD_S = 1.0
"""Paths and exploration goals are planned again this often."""
CAN_EXCLUSION_RADIUS_M = 0.25
"""Range returns within this of the target can's estimated centre are the can (or its shadow),
not an obstacle; below stop_distance + CAN_RADIUS_M the direct approach never brings the robot
to them."""
OBSTACLE_MEMORY_S = 15.0
"""The safety layer avoids a remembered obstacle until scans have had it in their blind zone
(nearer than range_min, at any bearing: no ray can clear a phantom there and no turn brings it
into view) for this long since one last saw it; farther out of view it is kept until a scan
sees its place free."""
UNKNOWN_FLOOR_WAIT_S = 5.0
"""The safety layer keeps the robot off floor no sensor has observed; unknown floor that has
been in a scan's blind disc (nearer than range_min, where no turn can observe it) for this long
is taken for floor, unless it lies within 0.3 m of a remembered obstacle."""
CAMERA_INFO_TIMEOUT_FACTOR = 2.0
"""camera_info may be this many times ~input_timeout old: drivers publish it with every image,
and a late one only limits driving to turning."""

TUNING = dict(
    can_radius=CAN_RADIUS_M, can_height=CAN_HEIGHT_M, min_confidence=MIN_CONFIDENCE,
    track_confidence=TRACK_CONFIDENCE, track_gate=TRACK_GATE_M,
    distance_tolerance=DISTANCE_TOLERANCE_M, bearing_tolerance_deg=BEARING_TOLERANCE_DEG,
    reapproach_distance=REAPPROACH_DISTANCE_M, reapproach_bearing_deg=REAPPROACH_BEARING_DEG,
    min_linear=MIN_LINEAR_MPS, min_angular=MIN_ANGULAR_RADPS, linear_gain=LINEAR_GAIN_PER_S,
    angular_gain=ANGULAR_GAIN_PER_S, turn_in_place_deg=TURN_IN_PLACE_DEG,
    search_angular=SEARCH_ANGULAR_RADPS, lost_timeout=LOST_TIMEOUT_S,
    vanish_timeout=VANISH_TIMEOUT_S, grid_resolution=GRID_RESOLUTION_M, map_size=MAP_SIZE_M,
    coverage_range=COVERAGE_RANGE_M, plan_margin=PLAN_MARGIN_M,
    explore_turn_cost=EXPLORE_TURN_COST_M_PER_RAD, replan_period=REPLAN_PERIOD_S,
    can_exclusion_radius=CAN_EXCLUSION_RADIUS_M, obstacle_memory=OBSTACLE_MEMORY_S,
    unknown_floor_wait=UNKNOWN_FLOOR_WAIT_S)
"""The constants above by the settings name the controller's parts read them under."""


def controller_settings(params, **tuning) -> SimpleNamespace:
    """The settings of the controller's parts: ``params`` (the can_stopper parameters), the
    constants of :data:`TUNING` (``tuning`` replaces some, for tests of what they bound), and
    what follows from the parameters: every input's timeout from ``input_timeout``
    (camera_info's CAMERA_INFO_TIMEOUT_FACTOR times it) and the exploring speed."""
    values = dict(vars(params))
    timeout_s = values['input_timeout']
    values.update(detection_timeout=timeout_s, scan_timeout=timeout_s, odom_timeout=timeout_s,
                  camera_info_timeout=CAMERA_INFO_TIMEOUT_FACTOR * timeout_s,
                  explore_linear=min(EXPLORE_LINEAR_MPS, values['max_linear']))
    values.update(TUNING)
    values.update(tuning)
    return SimpleNamespace(**values)
