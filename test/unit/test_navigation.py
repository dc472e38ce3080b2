"""World map, coverage, planning, the safety layer and exploration, without a simulator."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from can_seeker.camera_geometry import camera_pose_from_mount, intrinsics_from_vertical_fov
from can_seeker.camera_mount import CameraMount
from can_seeker.control import avoidance, planner
from can_seeker.control.controller import PARAMS, Controller
from can_seeker.control.tuning import controller_settings
from can_seeker.control.reasons import Because, Kind
from can_seeker.control.recoveries.stall import APPROACH_STALL_BEYOND_MEMORY_S
from can_seeker.control.sighting import Sighting
from can_seeker.control.supervisor import Event, State
from can_seeker.control.navigation import Navigator, Pose2D, camera_view
from can_seeker.control.scan_points import scan_rays
from kinematic_world import CAMERA_VIEW, ROBOT_RADIUS, World, run
from can_seeker.params import defaults

DEFAULTS = vars(controller_settings(defaults(PARAMS)))


def make_controller(**overrides):
    return Controller(SimpleNamespace(**dict(DEFAULTS, **overrides)))


# Camera view ---------------------------------------------------------------------------------

def nudged(values, steps):
    """``values`` moved ``steps`` ulps, up for positive ``steps``, down for negative."""
    values = np.asarray(values, float)
    for _ in range(abs(steps)):
        values = np.nextafter(values, math.copysign(math.inf, steps))
    return values


def test_camera_view_of_the_default_mount():
    pose = camera_pose_from_mount(CameraMount(0.25, 25.0))
    view = camera_view(pose, intrinsics_from_vertical_fov(320, 240, 45.0), 2.5, 0.122)
    assert view.x == pytest.approx(0.12)
    assert view.half_fov_rad == pytest.approx(math.atan(160.0 / 289.706), rel=1e-3)
    bottom_m = 0.25 / math.tan(math.radians(25.0 + 22.5))
    assert view.near_m == pytest.approx(bottom_m * (1.0 - 0.122 / 0.25), rel=1e-2)
    assert view.far_m == 2.5
    assert view.base_near_m == pytest.approx(bottom_m, rel=1e-2)


def test_a_high_camera_pitched_little_sees_the_floor_from_farther():
    pose = camera_pose_from_mount(CameraMount(0.34, 15.0))
    view = camera_view(pose, intrinsics_from_vertical_fov(320, 240, 45.0), 2.5, 0.122)
    assert view.base_near_m == pytest.approx(0.34 / math.tan(math.radians(15.0 + 22.5)), rel=1e-2)


# Planning ------------------------------------------------------------------------------------

def test_inflate_grows_by_the_radius():
    blocked = np.zeros((11, 11), bool)
    blocked[5, 5] = True
    grown = planner.inflate(blocked, 2.0)
    assert grown[5, 7] and grown[7, 5] and not grown[5, 8] and not grown[7, 7]


def test_wavefront_path_goes_around_a_wall():
    free = np.ones((20, 20), bool)
    free[10, 0:15] = False
    distance = planner.wavefront(free, (5, 5))
    path = planner.descend(distance, (15, 5))
    assert path[0] == (5, 5) and path[-1] == (15, 5)
    assert all(free[cell] for cell in path)
    assert max(cell[1] for cell in path) >= 15
    assert distance[15, 5] > 20


def test_unreachable_goal_has_no_path():
    free = np.ones((10, 10), bool)
    free[5, :] = False
    assert not np.isfinite(planner.wavefront(free, (2, 2))[8, 2])


def test_frontier_prefers_near_and_ahead():
    seen = np.zeros((30, 30), bool)
    seen[10:20, 10:20] = True
    blocked = np.zeros_like(seen)
    distance = planner.wavefront(~blocked, (15, 15))
    ahead = planner.frontier_goal(distance, seen, blocked, (15, 15), 0.0, 0.1, 0.3, 6)
    behind = planner.frontier_goal(distance, seen, blocked, (15, 15), math.pi, 0.1, 0.3, 6)
    assert ahead[0] == 20 and behind[0] == 9


def test_frontier_keeps_its_goal_until_another_costs_clearly_less():
    """A square of seen floor around the robot: facing +x it takes the goal ahead. Turned to
    face +y, a goal that way costs 0.47 m less (the turn) and would be taken afresh, but the
    one chosen is kept; unseen floor 0.9 m ahead, 0.57 m cheaper, replaces it."""
    seen = np.zeros((40, 40), bool)
    seen[10:30, 10:30] = True
    blocked = np.zeros_like(seen)
    distance = planner.wavefront(~blocked, (20, 20))
    ahead = planner.frontier_goal(distance, seen, blocked, (20, 20), 0.0, 0.1, 0.3, 6)
    assert ahead[0] == 30
    turned = math.pi / 2 + 0.1
    flipped = planner.frontier_goal(distance, seen, blocked, (20, 20), turned, 0.1, 0.3, 6)
    kept = planner.frontier_goal(distance, seen, blocked, (20, 20), turned, 0.1, 0.3, 6,
                                 previous=ahead, switch_m=0.5)
    assert flipped != ahead and kept == ahead
    seen[20:24, 30:34] = False
    seen[20:24, 29] = False
    nearer = planner.frontier_goal(distance, seen, blocked, (20, 20), turned, 0.1, 0.3, 6,
                                   previous=ahead, switch_m=0.5)
    assert nearer != ahead


def test_of_two_mirror_goals_the_frontier_picks_one_whatever_the_heading_s_last_bits():
    """Facing the seen square's diagonal, two goals mirror each other about the heading at the
    same cost: a heading a few ulps off either way (as another CPU's kernels may compute it)
    picks the same one."""
    seen = np.zeros((30, 30), bool)
    seen[10:20, 10:20] = True
    blocked = np.zeros_like(seen)
    distance = planner.wavefront(~blocked, (15, 15))
    goals = {planner.frontier_goal(distance, seen, blocked, (15, 15),
                                   float(nudged(math.pi / 4.0, steps)), 0.1, 0.3, 6)
             for steps in range(-4, 5)}
    assert len(goals) == 1 and goals <= {(18, 20), (20, 18)}


def test_no_frontier_when_everything_reachable_was_seen():
    seen = np.ones((20, 20), bool)
    blocked = np.zeros_like(seen)
    distance = planner.wavefront(~blocked, (10, 10))
    assert planner.frontier_goal(distance, seen, blocked, (10, 10), 0.0, 0.1, 0.3, 6) is None


def test_steering_to_a_point_keeps_most_of_the_cruise_on_small_corrections():
    """A lookahead point a few degrees off costs little speed; none past the turn-in-place
    bearing, where the robot only turns (toward the point)."""
    limit = math.radians(25.0)
    ahead = avoidance.steer_to_point((1.0, 0.0), 0.3, limit, 2.0)
    assert ahead == (0.3, 0.0)
    linear, angular = avoidance.steer_to_point((math.cos(0.5 * limit), math.sin(0.5 * limit)),
                                               0.3, limit, 2.0)
    assert linear == pytest.approx(0.225)
    assert angular == pytest.approx(2.0 * 0.5 * limit)
    linear, angular = avoidance.steer_to_point((math.cos(-1.2 * limit), math.sin(-1.2 * limit)),
                                               0.3, limit, 2.0)
    assert linear == 0.0 and angular < 0.0


# Safety --------------------------------------------------------------------------------------

def test_free_travel_straight_and_on_an_arc():
    wall = np.array([[1.0, y] for y in np.linspace(-0.5, 0.5, 21)])
    assert avoidance.free_travel_m(wall, 0.3, 0.0, 0.2, 2.0) == pytest.approx(0.8, abs=0.03)
    assert avoidance.free_travel_m(np.array([[1.0, 0.5]]), 0.3, 0.0, 0.2, 2.0) == 2.0
    # turning left onto a point ahead on the left
    assert avoidance.free_travel_m(np.array([[0.7, 0.4]]), 0.3, 0.5, 0.2, 2.0) < 1.0


def test_points_behind_a_robot_that_drives_away_do_not_stop_it():
    assert avoidance.free_travel_m(np.array([[-0.15, 0.0]]), 0.3, 0.0, 0.2, 1.0) == 1.0
    assert avoidance.free_travel_m(np.array([[0.15, 0.0]]), 0.3, 0.0, 0.2, 1.0) == 0.0


def test_a_robot_too_close_to_a_point_may_leave_it_but_never_turn_into_it():
    beside = np.array([[-0.01, -0.19]])                   # within the clearance, on the right
    assert avoidance.free_travel_m(beside, 0.3, 0.0, 0.2, 1.0) == 1.0       # straight away
    assert avoidance.free_travel_m(beside, 0.3, 1.0, 0.2, 1.0) == 1.0       # turning left
    assert avoidance.free_travel_m(beside, 0.1, -1.0, 0.2, 1.0) < 0.05      # turning into it


def test_each_point_may_have_its_own_clearance():
    points = np.array([[1.0, 0.0], [0.8, 0.0]])
    assert avoidance.free_travel_m(points, 0.3, 0.0, np.array([0.2, 0.05]), 2.0) == \
        pytest.approx(0.74, abs=0.03)
    assert avoidance.free_travel_m(points, 0.3, 0.0, np.array([0.5, 0.05]), 2.0) == \
        pytest.approx(0.5, abs=0.03)


def test_safe_linear_brakes_before_the_obstacle():
    assert avoidance.safe_linear(0.4, 2.0, 0.5, 0.03) == 0.4
    assert avoidance.safe_linear(0.4, 0.1, 0.5, 0.03) == pytest.approx(math.sqrt(2 * 0.5 * 0.07))
    assert avoidance.safe_linear(0.4, 0.02, 0.5, 0.03) == 0.0


def test_backing_up_brakes_before_the_obstacle_too():
    assert avoidance.safe_linear(-0.1, 2.0, 0.5, 0.03) == -0.1
    assert avoidance.safe_linear(-0.4, 0.1, 0.5, 0.03) == pytest.approx(-math.sqrt(2 * 0.5 * 0.07))
    assert avoidance.safe_linear(-0.1, 0.0, 0.5, 0.03) == 0.0


def test_an_unknown_free_travel_allows_no_motion():
    assert avoidance.safe_linear(0.4, math.nan, 0.5, 0.03) == 0.0
    assert avoidance.safe_linear(-0.1, math.nan, 0.5, 0.03) == 0.0


def test_free_travel_backing_up_straight_and_on_an_arc():
    behind = np.array([[-0.5, 0.0]])
    assert avoidance.free_travel_m(behind, -0.1, 0.0, 0.2, 1.0) == pytest.approx(0.3, abs=0.03)
    assert avoidance.free_travel_m(behind, 0.1, 0.0, 0.2, 1.0) == 1.0
    # backing up while turning left swings the back to the right, onto a point there
    behind_right = np.array([[-0.6, -0.25]])
    assert avoidance.free_travel_m(behind_right, -0.2, 0.5, 0.25, 1.0) < 0.5
    assert avoidance.free_travel_m(behind_right, -0.2, -0.5, 0.25, 1.0) == 1.0


def test_clear_heading_picks_the_gap_nearest_the_target():
    wall = np.array([[0.5, y] for y in np.linspace(-1.0, 0.2, 25)])
    heading = avoidance.clear_heading(wall, 0.0, 0.2, 0.5)
    assert heading > math.radians(20.0)
    assert avoidance.clear_heading(np.zeros((0, 2)), 0.3, 0.2, 0.5) == pytest.approx(0.3)


def test_frames_round_trip():
    points = np.array([[1.0, 2.0], [-0.5, 0.3]])
    back = avoidance.from_frame(avoidance.to_frame(points, 0.4, -0.2, 1.1), 0.4, -0.2, 1.1)
    assert np.allclose(back, points)


def test_the_target_can_is_not_an_obstacle():
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    can = np.array([[0.6, 0.0]])
    navigator.add_scan(can, np.array([True]), (0.0, 0.0), navigator.pose)
    assert navigator.free_travel_m((0.3, 0.0), unknown=False) < 0.5
    assert navigator.free_travel_m((0.3, 0.0), (0.6, 0.0), 0.15, unknown=False) == 1.0


def test_following_a_path_says_why_it_only_turns():
    """A robot that turns in place toward its path says why it does not drive: the path lies
    behind it, or no heading is clear; it says nothing while it drives."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    ahead, behind = np.array([[0.2, 0.0], [1.0, 0.0]]), np.array([[-0.2, 0.0], [-1.0, 0.0]])
    (linear, _), why = navigator.follow(ahead, 0.3, math.radians(25.0), 2.0)
    assert linear > 0.0 and why is None
    (linear, angular), why = navigator.follow(behind, 0.3, math.radians(25.0), 2.0)
    assert linear == 0.0 and angular != 0.0 and why.kind is Kind.TURNING_TO_PATH
    ring = 0.25 * np.stack((np.cos(np.linspace(0, 2 * math.pi, 72, endpoint=False)),
                            np.sin(np.linspace(0, 2 * math.pi, 72, endpoint=False))), axis=1)
    navigator.add_scan(ring, np.ones(len(ring), bool), (0.0, 0.0), navigator.pose)
    (linear, angular), why = navigator.follow(ahead, 0.3, math.radians(25.0), 2.0)
    assert linear == 0.0 and angular != 0.0 and why.kind is Kind.NO_CLEAR_HEADING


def wall_navigator(wall_xy, pose):
    """A navigator at ``pose`` that has seen obstacles at the odom points ``wall_xy``."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = pose
    ends = avoidance.to_frame(np.asarray(wall_xy, float), pose.x, pose.y, pose.yaw)
    for _ in range(3):
        navigator.add_scan(ends, np.ones(len(ends), bool), (0.0, 0.0), pose)
    return navigator


def clearance_of(path_xy, wall_xy):
    """Nearest distance (m) from each path point to the obstacle points."""
    return np.min(np.linalg.norm(np.asarray(path_xy)[:, None, :]
                                 - np.asarray(wall_xy)[None, :, :], axis=2), axis=1)


def test_a_passage_too_narrow_for_the_plan_margin_is_a_way_the_safety_layer_allows():
    """A 0.7 m gap in a wall (a doorway, the floor between a table and a wall) is too narrow
    for the robot plus ``plan_margin`` on both sides, but wide enough for the safety layer's
    own margin: paths and exploration go through it, along its middle."""
    wall = np.array([(1.0, y) for y in np.arange(-4.9, 4.91, 0.05) if abs(y) >= 0.35])
    navigator = wall_navigator(wall, Pose2D(0.0, 0.0, 0.0))
    path = navigator.path_to((2.0, 0.0))
    assert path is not None
    assert np.all(clearance_of(path, wall) > 0.165 + 0.05)
    navigator.world.coverage.seen[:navigator.world.cell_of(1.1, 0.0)[0], :] = True
    goal = navigator.frontier(0.3, 6)
    assert goal is not None and goal[0] > 1.0


def test_a_robot_within_the_plan_margin_leaves_it_and_keeps_it_on_the_way():
    """A robot that stands nearer a wall than ``plan_margin`` allows may plan its way out of
    that margin, but not along the wall inside it."""
    wall = np.array([(x, 0.5) for x in np.arange(-1.0, 3.01, 0.05)])
    navigator = wall_navigator(wall, Pose2D(0.0, 0.25, 0.0))
    path = navigator.path_to((2.0, 0.15))
    assert path is not None
    beyond_start = np.linalg.norm(path - (0.0, 0.25), axis=1) > 0.45
    assert np.any(beyond_start)
    assert np.all(clearance_of(path[beyond_start], wall) >= 0.165 + 0.15 - 1e-6)


def side_of(path_xy):
    """+1 when a path passes the obstacle at y = 0 on its left (y > 0), -1 on its right."""
    return int(np.sign(np.asarray(path_xy)[:, 1].sum()))


DISC = np.array([(1.0 + 0.3 * math.cos(a), 0.3 * math.sin(a))
                 for a in np.linspace(0.0, 2.0 * math.pi, 60)])


def test_a_path_about_an_obstacle_is_kept_while_the_other_way_is_hardly_shorter():
    """Two ways about a round obstacle of about the same length: once the robot follows one,
    a plan from a pose where the other is a little shorter keeps the first. Choosing afresh
    at every plan, the robot turned to each way in turn and went neither."""
    first = wall_navigator(DISC, Pose2D(0.0, 0.0, 0.0)).path_to((2.0, 0.0))
    side = side_of(first)
    navigator = wall_navigator(DISC, Pose2D(0.0, -0.1 * side, 0.0))
    assert side_of(navigator.path_to((2.0, 0.0))) == -side
    kept = navigator.path_to((2.0, 0.0), previous_xy=first)
    assert side_of(kept) == side
    assert np.allclose(kept[-1], first[-1])


def test_a_kept_path_gives_way_when_blocked_or_much_longer_or_to_another_goal():
    first = wall_navigator(DISC, Pose2D(0.0, 0.0, 0.0)).path_to((2.0, 0.0))
    side = side_of(first)
    wall = np.array([(1.0, side * y) for y in np.arange(0.3, 3.0, 0.05)])
    blocked = wall_navigator(np.vstack((DISC, wall)), Pose2D(0.0, 0.0, 0.0))
    assert side_of(blocked.path_to((2.0, 0.0), previous_xy=first)) == -side
    far_side = wall_navigator(DISC, Pose2D(0.0, -0.6 * side, 0.0))
    assert side_of(far_side.path_to((2.0, 0.0), previous_xy=first)) == -side
    other_goal = wall_navigator(DISC, Pose2D(0.0, 0.0, 0.0)).path_to((2.0, 0.5),
                                                                      previous_xy=first)
    assert np.linalg.norm(other_goal[-1] - (2.0, 0.5)) < 0.1


# Controller ----------------------------------------------------------------------------------

OBSTACLES = [(1.2, 1.2, 0.25), (-1.0, 1.0, 0.2), (0.8, -1.4, 0.3), (-1.5, -1.0, 0.25),
             (1.8, 0.3, 0.15), (-0.2, 1.9, 0.3)]


def stopped(controller):
    return controller.state is State.STOPPED


def test_without_a_scan_the_robot_does_not_drive_forward():
    controller = make_controller()
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe(None, 0.0)
    controller.supervisor.handle(Event.SEARCHED_ALL_ROUND, 0.0)
    for step in range(20):
        controller.observe(None, step * 0.05)
        controller.observe_pose(Pose2D(0.0, 0.0, 0.0), step * 0.05)
        assert controller.command(step * 0.05)[0] == 0.0


def test_search_explores_after_a_full_turn_and_finds_a_hidden_can():
    world = World(3.0, OBSTACLES, (2.5, 2.5))
    controller = make_controller()
    now, poses, states, clearance = run(controller, world, 90.0, stop_when=stopped)
    assert controller.state is State.STOPPED
    assert State.EXPLORE in states
    assert states.index(State.EXPLORE) / 20.0 == pytest.approx(2 * math.pi / 0.8, abs=1.0)
    assert clearance > 0.0
    gap = math.hypot(world.pose.x - 2.5, world.pose.y - 2.5) - 0.033 - ROBOT_RADIUS
    assert gap == pytest.approx(DEFAULTS['stop_distance'], abs=0.02)


def test_with_a_lidar_exploration_heads_first_for_the_small_object_it_saw():
    """The lidar sees the can across the room as a small object standing free (the kinematic
    world's lidar sees it as a 0.03 m post): after the SEARCH turn, which does not show it,
    the first exploration goal is that place, not the nearest uncovered floor."""
    can = (-2.3, -2.3)
    world = World(3.0, OBSTACLES + [(can[0], can[1], 0.03)], can)
    controller = make_controller()
    run(controller, world, 30.0, stop_when=lambda c: c.state is State.EXPLORE)
    assert controller.state is State.EXPLORE
    explore = controller.parts.explore
    assert explore.goal_is_candidate
    assert math.hypot(explore.goal_xy[0] - can[0], explore.goal_xy[1] - can[1]) < 0.1
    now, poses, states, clearance = run(controller, world, 60.0, stop_when=stopped,
                                        start_s=30.0)
    assert controller.state is State.STOPPED
    assert clearance > 0.0


def test_exploration_keeps_a_candidate_goal_while_the_robot_gets_nearer_over_covered_floor():
    controller = make_controller()
    controller.navigator.world.coverage.seen[:] = True
    controller.navigator.world.candidates.points.append(np.array([3.0, 0.0]))
    controller.navigator.world.candidates.viewed.append(False)
    controller.navigator.pose = Pose2D(0.0, 0.0, 0.0)
    assert controller.navigator.unviewed_candidate() is not None
    controller.supervisor.handle(Event.SEARCHED_ALL_ROUND, 0.0)
    explore, give_up = controller.parts.explore, controller.parts.give_up
    explore.goal_xy, explore.goal_is_candidate = np.array([3.0, 0.0]), True
    for step in range(200):                                  # 10 s at 0.1 m/s, nothing new seen
        controller.navigator.pose = Pose2D(0.005 * step, 0.0, 0.0)
        give_up.after_tick(State.EXPLORE, 0.05 * step, Because())
    assert explore.goal_xy is not None
    for step in range(200, 400):                             # 10 s standing
        give_up.after_tick(State.EXPLORE, 0.05 * step, Because())
    assert explore.goal_xy is None                           # given up
    assert controller.navigator.unviewed_candidate() is None


def test_a_place_chosen_after_stalled_floor_gets_its_own_stall_time():
    controller = make_controller()
    controller.navigator.pose = Pose2D(0.0, 0.0, 0.0)
    controller.supervisor.handle(Event.SEARCHED_ALL_ROUND, 0.0)
    explore, give_up = controller.parts.explore, controller.parts.give_up
    explore.goal_xy = np.array([1.0, 1.0])                   # floor; nothing new seen for 5 s
    for step in range(100):
        give_up.after_tick(State.EXPLORE, 0.05 * step, Because())
    controller.navigator.world.candidates.points.append(np.array([3.0, 0.0]))
    controller.navigator.world.candidates.viewed.append(False)
    explore.goal_xy, explore.goal_is_candidate = np.array([3.0, 0.0]), True
    for step in range(100, 200):                              # 5 s more, standing
        give_up.after_tick(State.EXPLORE, 0.05 * step, Because())
    assert explore.goal_xy is not None
    assert controller.navigator.unviewed_candidate() is not None


def test_arriving_at_a_place_where_the_can_may_stand_counts_it_as_looked_at():
    controller = make_controller()
    navigator = controller.navigator
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.world.candidates.points.append(np.array([0.2, 0.0]))
    navigator.world.candidates.viewed.append(False)
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe_scan(controller.scan_sources[0], np.array([[2.0, 0.0]]), np.array([False]),
                            (0.0, 0.0), 0.0)
    controller.observe_camera_info(0.0)
    controller.observe(None, 0.0)
    controller.supervisor.handle(Event.SEARCHED_ALL_ROUND, 0.0)
    controller.command(0.0)
    assert controller.state is State.SEARCH
    assert navigator.unviewed_candidate() is None


def test_approach_goes_around_an_obstacle_between_robot_and_can():
    world = World(3.0, [(1.0, 0.0, 0.3)], (2.2, 0.0))
    controller = make_controller()
    now, poses, states, clearance = run(controller, world, 60.0, stop_when=stopped)
    assert controller.state is State.STOPPED
    assert clearance > 0.0
    assert max(abs(pose.y) for pose in poses) > 0.4


def test_an_approach_that_gets_no_nearer_switches_to_keeping_to_its_path():
    """APPROACH 2 m from the can, no nearer for OBSTACLE_MEMORY_S + 5 s (cycling between the
    path about a corner and the direct law, or standing): it keeps to a path, and the can
    leaving the view no longer makes it LOST. As long again without getting nearer: back to
    the usual way. Coming 0.2 m nearer starts the count again."""
    controller = make_controller()
    stall_s = DEFAULTS['obstacle_memory'] + APPROACH_STALL_BEYOND_MEMORY_S
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe_scan(controller.scan_sources[0], np.array([[3.0, 0.0]]),
                            np.array([False]), (0.0, 0.0), 0.0)
    controller.observe(Sighting(1.8, 0.0, 1.0), 0.0)
    assert controller.state is State.APPROACH
    keep = controller.parts.keep_to_path
    for step in range(int(stall_s / 0.05) + 1):
        keep.after_tick(controller.state, 0.05 * step, Because())
    assert not keep.active
    keep.after_tick(controller.state, stall_s + 0.1, Because())
    assert keep.active
    controller.observe(None, stall_s + 0.2)
    assert controller.state is State.APPROACH
    assert controller.sighting.gap_m == pytest.approx(1.8)
    nearer_s = stall_s + 5.0
    controller.observe_pose(Pose2D(0.25, 0.0, 0.0), nearer_s)
    keep.after_tick(controller.state, nearer_s, Because())
    keep.after_tick(controller.state, nearer_s + stall_s, Because())
    assert keep.active
    keep.after_tick(controller.state, nearer_s + stall_s + 0.1, Because())
    assert not keep.active
    controller.observe(None, nearer_s + stall_s + 0.2)
    assert controller.state is State.LOST


def ring_scan(origin_xy, centre_xy, radius_m, max_range_m=3.0):
    """(ends, hits) in a frame at ``origin_xy`` (yaw 0) of rays all round to a circle of
    obstacles about ``centre_xy``."""
    angles = np.linspace(-math.pi, math.pi, 720, endpoint=False)
    rays = np.stack((np.cos(angles), np.sin(angles)), axis=-1)
    centre = np.asarray(centre_xy, float) - np.asarray(origin_xy, float)
    along = rays @ centre
    across_sq = centre @ centre - along ** 2
    hits = (across_sq <= radius_m ** 2) & (along > 0.0)
    ranges = np.where(hits, along - np.sqrt(np.maximum(radius_m ** 2 - across_sq, 0.0)),
                      max_range_m)
    return rays * ranges[:, None], hits


def test_keeping_to_a_path_that_no_longer_reaches_the_can_backs_up():
    """After a stall APPROACH keeps to a path; with none to the can (a ring of obstacles about
    it, as a map that has closed the gap beside an obstacle's corner holds one) it backs up to
    see the way, where the usual way turns back to the straight line."""
    controller = make_controller()
    for now, origin in enumerate(((3.0, 0.0), (1.5, 1.5), (1.5, -1.5), (0.0, 0.0))):
        controller.observe_pose(Pose2D(origin[0], origin[1], 0.0), now)
        ends, hits = ring_scan(origin, (1.5, 0.0), 0.6)
        controller.observe_scan(controller.scan_sources[0], ends, hits, (0.0, 0.0), now)
    controller.observe_camera_info(3.0)
    controller.observe(Sighting(1.5 - ROBOT_RADIUS - DEFAULTS['can_radius'], 0.0, 1.0), 3.0)
    assert controller.state is State.APPROACH
    approach = controller.parts.approach
    controller.context.because = because = Because()
    usual = approach.command(3.0).command
    assert usual[0] >= 0.0
    controller.parts.keep_to_path.active = True
    controller.context.because = because = Because()
    assert approach.command(3.1).command == (-DEFAULTS['max_reverse'], 0.0)
    assert because.first.kind is Kind.NO_PATH_TO_CAN


def test_keeping_to_the_path_ends_near_the_can_and_outside_approach():
    """Within DIRECT_GAP_M the direct law stops in front of the can: the can leaving the view
    there is LOST again; and a new state other than APPROACH or LOST forgets the switch."""
    controller = make_controller()
    controller.observe_pose(Pose2D(0.0, 0.0, 0.0), 0.0)
    controller.observe(Sighting(0.4, 0.0, 1.0), 0.0)
    keep = controller.parts.keep_to_path
    keep.active = True
    controller.observe(None, 0.1)
    assert controller.state is State.LOST
    controller.supervisor.handle(Event.LOST_TIMEOUT, 0.2)
    assert not keep.active


CLUTTER = [(-1.27, 2.58, 0.155), (-0.01, -1.65, 0.21), (-1.57, 2.71, 0.15), (2.43, 1.61, 0.2),
           (-2.38, -1.68, 0.17), (-0.72, -1.09, 0.15)]


def test_a_camera_only_robot_keeps_its_margin_from_obstacles_that_left_its_view():
    """The camera scan sees +-29 deg and nothing nearer than the image's bottom row; on its way
    to a can hidden behind two cylinders the robot passes beside them after they have left the
    view, and turns toward the can past them: the safety layer must still know them, and keep
    its margin from wherever in their map cells they stand."""
    world = World(3.0, CLUTTER, (-0.15, -2.45))
    controller = make_controller()
    now, poses, states, clearance = run(controller, world, 90.0, stop_when=stopped,
                                        camera_scan=True)
    assert controller.state is State.STOPPED
    assert clearance > DEFAULTS['safety_margin'] / 2.0


def test_lost_facing_where_the_can_was_searches_at_once():
    """The can vanishes while the robot approaches it: LOST turns to face where it was, and
    seeing nothing there it searches within a second or so, not after LOST_TIMEOUT_S."""
    world = World(3.0, [], (1.2, 0.0))
    controller = make_controller()
    now, _, _, _ = run(controller, world, 30.0, stop_when=lambda c: (
        c.state is State.APPROACH and c.sighting.gap_m < 0.45))
    assert controller.state is State.APPROACH
    world.can_xy = (10.0, 10.0)
    _, _, states, _ = run(controller, world, 10.0, start_s=now,
                          stop_when=lambda c: c.state is State.SEARCH)
    assert states[-1] is State.SEARCH and State.LOST in states
    lost_s = (len(states) - states.index(State.LOST)) / 20.0
    assert lost_s < DEFAULTS['lost_timeout'] / 2.0
    assert controller.reason.kind is Kind.CAN_NOT_THERE


def test_wander_keeps_moving_without_touching_anything():
    world = World(2.0, OBSTACLES[:3])
    controller = make_controller(behaviour='wander')
    now, poses, states, clearance = run(controller, world, 60.0)
    assert set(states) == {State.WANDER}
    assert clearance > 0.0
    path_m = sum(math.hypot(b.x - a.x, b.y - a.y) for a, b in zip(poses, poses[1:]))
    assert path_m > 5.0


def test_scan_rays_follow_rep_117():
    ends, hits = scan_rays(-0.5, 0.5, [1.0, math.inf, math.nan, 0.01, 9.0], 0.05, 4.0)
    assert hits.tolist() == [True, False, False]
    assert ends[0] == pytest.approx([math.cos(-0.5), math.sin(-0.5)])
    assert np.hypot(*ends[1]) == pytest.approx(4.0) and np.hypot(*ends[2]) == pytest.approx(4.0)




def test_the_safety_layer_forgets_a_phantom_that_scans_keep_in_their_blind_zone():
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05, memory_s=10.0)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.add_scan(np.array([[0.5, 0.0]]), np.array([True]), (0.0, 0.0), navigator.pose,
                       stamp_s=0.0)
    ahead = np.array([[2.0, 0.0]])
    navigator.add_scan(ahead, np.array([False]), (0.0, 0.0), navigator.pose, range_min_m=1.0,
                       stamp_s=5.0)
    assert navigator.free_travel_m((0.3, 0.0), unknown=False) < 0.5          # 5 s in the blind zone
    navigator.add_scan(ahead, np.array([False]), (0.0, 0.0), navigator.pose, range_min_m=1.0,
                       stamp_s=11.0)
    assert navigator.free_travel_m((0.3, 0.0), unknown=False) == 1.0         # 11 s in the blind zone
    assert navigator.world.occupied()[navigator.world.cell_of(0.5, 0.0)]     # still on the map



def test_an_obstacle_cut_by_the_image_bottom_keeps_what_is_remembered_nearer():
    """A box 0.22 m ahead fills the bottom of a camera's image: its scan reports it at its
    range_min (0.35 m), where it is at most. The box's cells nearer than that, remembered from
    earlier, stay while the scan keeps reporting it there (they are no phantom: something is
    seen at the edge of the blind zone); once that ray shows free floor, they are dropped after
    the memory time as before."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05, memory_s=10.0)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.add_scan(np.array([[0.22, 0.0]]), np.array([True]), (0.0, 0.0), navigator.pose,
                       stamp_s=0.0)
    at_edge = np.array([[0.35, 0.0]])
    for stamp_s in range(1, 31):
        navigator.add_scan(at_edge, np.array([True]), (0.0, 0.0), navigator.pose,
                           range_min_m=0.35, stamp_s=float(stamp_s))
    assert navigator.free_travel_m((0.1, 0.0), unknown=False) < 0.01
    for stamp_s in range(31, 43):
        navigator.add_scan(np.array([[2.0, 0.0]]), np.array([False]), (0.0, 0.0),
                           navigator.pose, range_min_m=0.35, stamp_s=float(stamp_s))
    assert navigator.free_travel_m((0.1, 0.0), unknown=False) > 0.1

def test_a_remembered_obstacle_is_kept_where_it_was_hit_not_at_its_cell_centre():
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, math.pi / 2.0)
    # hit beside the path, 0.205 m to the right (its cell's centre is 0.25 m away)
    navigator.add_scan(np.array([[0.3, -0.205]]), np.array([True]), (0.0, 0.0), navigator.pose,
                       stamp_s=0.0)
    navigator.add_scan(np.array([[1.0, 0.0]]), np.array([False]), (0.0, 0.0), navigator.pose,
                       range_min_m=0.9, stamp_s=1.0)
    assert len(navigator.safety.last_scans[''][0]) == 0               # only remembered now
    assert navigator.free_travel_m((0.3, 0.0), unknown=False) < 0.35
    navigator.pose = Pose2D(-0.1, 0.0, math.pi / 2.0)          # 0.305 m from it
    assert navigator.free_travel_m((0.3, 0.0), unknown=False) == 1.0




def test_the_safety_layer_keeps_an_obstacle_out_of_view_until_a_scan_sees_its_place_free():
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05, memory_s=10.0)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.add_scan(np.array([[0.45, 0.0]]), np.array([True]), (0.0, 0.0), navigator.pose,
                       stamp_s=0.0)
    navigator.pose = Pose2D(0.15, 0.0, math.pi / 2.0)        # now 0.3 m to the robot's right
    for stamp_s in range(1, 61):                              # a minute looking ahead only
        navigator.add_scan(np.array([[2.0, 0.0]]), np.array([False]), (0.0, 0.0),
                           navigator.pose, range_min_m=0.25, stamp_s=float(stamp_s))
    sharp_right = (0.1, -1.0)                                 # a 0.1 m radius arc into it
    assert navigator.free_travel_m(sharp_right) < 0.1
    navigator.pose = Pose2D(0.15, 0.0, 0.0)                   # turned toward it, sees it free
    for stamp_s in range(61, 81):
        navigator.add_scan(np.array([[2.0, 0.0]]), np.array([False]), (0.0, 0.0),
                           navigator.pose, range_min_m=0.1, stamp_s=float(stamp_s))
    assert not navigator.world.occupied()[navigator.world.cell_of(0.45, 0.0)]


def test_the_safety_layer_forgets_a_phantom_beside_the_robot_in_the_blind_disc():
    """Beside the robot, nearer than the scan's range_min, no ray reaches a remembered
    obstacle and no turn brings it into view: a phantom there (a frame that took a floor tile
    for an obstacle) would hold the robot for ever, so after OBSTACLE_MEMORY_S in that blind
    disc the safety layer lets it go, as it does ahead. The map (and so the planner) keeps it."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05, memory_s=10.0)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.add_scan(np.array([[0.45, 0.0]]), np.array([True]), (0.0, 0.0), navigator.pose,
                       stamp_s=0.0)
    navigator.pose = Pose2D(0.15, 0.0, math.pi / 2.0)        # now 0.3 m to the robot's right
    sharp_right = (0.1, -1.0)
    for stamp_s in range(1, 6):
        navigator.add_scan(np.array([[2.0, 0.0]]), np.array([False]), (0.0, 0.0),
                           navigator.pose, range_min_m=0.35, stamp_s=float(stamp_s))
    assert navigator.free_travel_m(sharp_right, unknown=False) < 0.1     # 5 s in the disc
    for stamp_s in range(6, 12):
        navigator.add_scan(np.array([[2.0, 0.0]]), np.array([False]), (0.0, 0.0),
                           navigator.pose, range_min_m=0.35, stamp_s=float(stamp_s))
    assert navigator.free_travel_m(sharp_right, unknown=False) > 0.3     # 11 s in the disc
    assert navigator.world.occupied()[navigator.world.cell_of(0.45, 0.0)]




def fan(first_deg, last_deg, range_m, step_deg=1.0):
    """Ray ends (N x 2) of a scan without returns from ``first_deg`` to ``last_deg``."""
    angles = np.radians(np.arange(first_deg, last_deg + 1e-9, step_deg))
    return range_m * np.stack((np.cos(angles), np.sin(angles)), axis=1)


def test_floor_beside_the_robot_that_no_ray_reached_keeps_it_from_arcing_there():
    """A camera looks ahead: an obstacle beside the robot is out of its view, the floor there
    never observed. The robot may drive straight and arc away from it, not into it, until a scan
    has observed that floor."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    all_but_left = np.concatenate((fan(-180.0, 50.0, 1.2), fan(130.0, 179.0, 1.2)))
    navigator.add_scan(all_but_left, np.zeros(len(all_but_left), bool), (0.0, 0.0),
                       navigator.pose, range_min_m=0.25)
    left_arc, right_arc = (0.2, 1.0), (0.2, -1.0)
    assert navigator.free_travel_m((0.3, 0.0)) == 1.0
    assert navigator.free_travel_m(right_arc) == 1.0
    assert navigator.free_travel_m(left_arc) < 0.3
    assert navigator.free_travel_m(left_arc, unknown=False) == 1.0
    left = fan(40.0, 140.0, 1.2)
    navigator.add_scan(left, np.zeros(len(left), bool), (0.0, 0.0), navigator.pose,
                       range_min_m=0.25)
    assert navigator.free_travel_m(left_arc) == 1.0


def test_a_cell_the_rays_call_free_may_still_hold_an_unobserved_corner():
    """Rays graze an obstacle's corner at (0.45, 0.45): they clear the coarse cell it stands
    in (0.4-0.5 m square, most of it floor), but the fine cells beyond the corner stay unknown,
    and the robot keeps off them. The 42 deg ray's sample 0.6 m out enters that cell, well
    short of the ray's end (not on the knife edge of a ray exactly 12 steps long)."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    grazing = fan(38.0, 42.0, 0.62)                           # short of the corner's shadow
    elsewhere = np.concatenate((fan(-180.0, 37.0, 2.0), fan(54.0, 179.0, 2.0)))
    ends = np.concatenate((grazing, elsewhere))
    navigator.add_scan(ends, np.zeros(len(ends), bool), (0.0, 0.0), navigator.pose)
    assert navigator.world.obstacles.evidence[navigator.world.cell_of(0.45, 0.45)] < 0
    along_the_corner = Pose2D(-0.2, 0.475, 0.0)
    navigator.pose = along_the_corner
    assert navigator.free_travel_m((0.3, 0.0), unknown=False) == 1.0
    assert navigator.free_travel_m((0.3, 0.0)) < 0.45


def test_the_floor_the_robot_drove_over_is_observed():
    """Backing up along the way the robot came is free; backing up into floor nothing observed
    is not."""
    def drive_and_back_up(distance_m):
        navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
        ahead = fan(-45.0, 45.0, 1.0)
        for x_m in np.arange(0.0, distance_m + 1e-9, 0.02):
            navigator.pose = Pose2D(float(x_m), 0.0, 0.0)
            navigator.add_scan(ahead, np.zeros(len(ahead), bool), (0.0, 0.0), navigator.pose,
                               range_min_m=0.25)
        return navigator.free_travel_m((-0.1, 0.0))

    assert drive_and_back_up(0.0) < 0.2                       # the start disc only
    assert drive_and_back_up(0.6) >= 0.6


def test_unknown_floor_no_turn_can_observe_is_taken_for_floor_after_the_wait():
    """No ray can observe the floor nearer than range_min to the sensor, whichever way the robot
    turns: unknown floor that has been in that blind disc for UNKNOWN_FLOOR_WAIT_S stops holding
    the robot, so a robot set down where it never looked is not stuck for ever. Unknown floor
    farther out stays unknown until a scan observes it."""
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05, unknown_wait_s=5.0)
    ahead = fan(-30.0, 30.0, 1.5)

    def scan(stamp_s):
        navigator.add_scan(ahead, np.zeros(len(ahead), bool), (0.0, 0.0), navigator.pose,
                           range_min_m=0.45, stamp_s=stamp_s)

    navigator.pose = Pose2D(0.0, 0.0, math.pi)
    scan(0.0)
    navigator.pose = Pose2D(2.0, 0.0, 0.0)                    # carried elsewhere
    scan(1.0)
    assert navigator.free_travel_m((0.3, 0.0)) < 0.1
    for stamp_s in range(2, 8):
        scan(float(stamp_s))
    assert navigator.free_travel_m((0.3, 0.0)) == 1.0
    sharp_left = (0.1, 0.5)                                   # out to unknown floor beside
    assert navigator.free_travel_m(sharp_left) < navigator.free_travel_m(sharp_left,
                                                                         unknown=False)


def test_unknown_floor_beside_a_remembered_obstacle_is_not_taken_for_floor_by_waiting():
    """A camera saw one face of an obstacle, which now stands beside the robot in the scan's
    blind disc: how far it goes on into the floor nobody observed is unknown, so that floor
    keeps holding the robot after UNKNOWN_FLOOR_WAIT_S, while unknown floor elsewhere in the
    disc is taken for floor. Once the obstacle itself is let go (OBSTACLE_MEMORY_S in the
    disc), so is the floor around it."""
    navigator = Navigator(0.1, 4.0, 0.165, 0.15, 0.05, memory_s=15.0, unknown_wait_s=5.0)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.world.update_from_scan((0.0, 0.0), np.array([[0.45, 0.25]]), np.array([True]),
                                     stamp_s=0.0)
    beside_xy, elsewhere_xy = np.array([0.5, 0.45]), np.array([-0.45, -0.3])

    def unknown_near(xy, stamp_s):
        navigator.world.update_from_scan((0.0, 0.0), np.array([[0.0, -2.0]]),
                                         np.array([False]), 0.8, stamp_s=stamp_s)
        points, _ = navigator.safety.unknown_base(navigator.pose)
        return bool((np.linalg.norm(points - xy, axis=1) < 0.05).any())

    assert unknown_near(beside_xy, 1.0) and unknown_near(elsewhere_xy, 1.0)
    assert unknown_near(beside_xy, 8.0) and not unknown_near(elsewhere_xy, 8.0)
    assert not unknown_near(beside_xy, 20.0)


def test_an_obstacle_beside_the_last_stretch_moves_the_stop_point_around_the_can():
    """Half a metre from the can the robot sees an obstacle ahead-left, 0.26 m beside the
    straight line to the can, in five frames (as a specular highlight on the floor can give).
    Once it is beside the robot, out of the camera's view and in the camera scan's blind disc,
    no turn can clear it, and the straight approach would pass it within the safety margin:
    the robot stops at the can a little to its side, facing it, instead of standing short of
    it for ever."""
    world = World(3.0, [], (2.0, 0.0))
    controller = make_controller()
    now, _, _, _ = run(controller, world, 20.0, camera_scan=True, stop_when=lambda c: (
        c.state is State.APPROACH and c.sighting.gap_m < 0.5))
    pose = world.pose
    point_odom = avoidance.from_frame(np.array([0.3, 0.262]), pose.x, pose.y, pose.yaw)[0]
    for _ in range(5):
        controller.observe_scan(controller.scan_sources[0], np.array([[0.3, 0.262]]),
                                np.array([True]), (0.0, 0.0), now)
    assert controller.navigator.world.occupied()[controller.navigator.world.cell_of(*point_odom)]
    _, poses, states, _ = run(controller, world, 30.0, stop_when=stopped, camera_scan=True,
                              start_s=now)
    assert controller.state is State.STOPPED
    assert set(states) <= {State.APPROACH, State.STOPPED}
    gap = math.hypot(world.pose.x - 2.0, world.pose.y) - 0.033 - ROBOT_RADIUS
    assert gap == pytest.approx(DEFAULTS['stop_distance'], abs=DEFAULTS['distance_tolerance'])
    nearest = min(math.hypot(p.x - point_odom[0], p.y - point_odom[1]) for p in poses)
    assert nearest >= ROBOT_RADIUS + DEFAULTS['safety_margin']


def test_with_the_last_stretch_clear_the_robot_stops_straight_in_front_of_the_can():
    world = World(3.0, [], (1.5, 0.0), Pose2D(0.86, 0.0, 0.0))
    controller = make_controller()
    _, poses, _, _ = run(controller, world, 20.0, stop_when=stopped, camera_scan=True)
    assert controller.state is State.STOPPED
    assert max(abs(pose.y) for pose in poses) < 1e-6


def test_straight_free_travel_is_the_free_travel_of_each_heading():
    points = np.array([[0.6, 0.1], [0.2, -0.5], [-0.4, 0.3], [0.1, 0.25]])
    clearance = np.array([0.2, 0.25, 0.2, 0.3])
    headings = np.radians(np.arange(-180.0, 180.0, 7.5))
    travel = avoidance.straight_free_travel_m(points, headings, clearance, 1.0)
    for heading, free_m in zip(headings, travel):
        facing = avoidance.to_frame(points, 0.0, 0.0, heading)
        assert free_m == pytest.approx(avoidance.free_travel_m(facing, 0.3, 0.0, clearance, 1.0))
    assert avoidance.straight_free_travel_m(np.zeros((0, 2)), headings, 0.2, 1.0).tolist() \
        == [1.0] * len(headings)


def test_within_the_stop_tolerance_the_robot_faces_the_can_instead_of_a_stop_point_aside():
    """The gap is 7 mm longer than stop_distance (within DISTANCE_TOLERANCE_M, beyond half of
    it) and the can is 8 deg to the right, while an obstacle ahead-right holds even a 3 cm drive
    back: the robot turns to face the can and stops, instead of turning 40 deg away to a stop
    point beside the can and back each time the gap's estimate crosses half the tolerance."""
    controller = make_controller()
    gap_m = DEFAULTS['stop_distance'] + 0.007
    bearing = math.radians(-8.0)
    pose = Pose2D(0.0, 0.0, 0.0)
    blocked = fan(-180.0, 180.0, 1.5)
    blocked = np.vstack((blocked, [[0.17, -0.13]]))
    hits = np.zeros(len(blocked), bool)
    hits[-1] = True
    controller.set_camera_view(CAMERA_VIEW)
    for step in range(40):
        now = step * 0.05
        controller.observe_pose(pose, now)
        controller.observe_scan(controller.scan_sources[0], blocked, hits, (0.0, 0.0), now)
        controller.observe(Sighting(gap_m, bearing - pose.yaw), now)
        linear, angular = controller.command(now)
        assert controller.reason is None or controller.reason.kind is not \
            Kind.TURNING_TO_STOP_ASIDE, (step, controller.why)
        assert linear == 0.0 and angular <= 0.0, (step, linear, angular)
        pose = Pose2D(0.0, 0.0, pose.yaw + angular * 0.05)
        if controller.state is State.STOPPED:
            break
    assert controller.state is State.STOPPED
    assert abs(pose.yaw - bearing) <= math.radians(DEFAULTS['bearing_tolerance_deg'])
