"""The controller's parts, built from its parameters and wired together (the composition the
:class:`~can_seeker.control.controller.Controller` facade fronts)."""
from can_seeker.control.behaviours.approach import Approach
from can_seeker.control.behaviours.base import Context
from can_seeker.control.behaviours.explore import Explore
from can_seeker.control.behaviours.idle import Idle
from can_seeker.control.behaviours.lost import Lost
from can_seeker.control.behaviours.path_following import PathFollower
from can_seeker.control.behaviours.search import Search
from can_seeker.control.behaviours.stopped import Stopped
from can_seeker.control.behaviours.wander import Wander
from can_seeker.control.bump_recovery import BumpRecovery
from can_seeker.control.can_tracker import CanTracker
from can_seeker.control.input_freshness import InputFreshness
from can_seeker.control.navigation import Navigator
from can_seeker.control.recoveries.floor import BackUpToSeeFloor, TurnToLook
from can_seeker.control.recoveries.stall import GiveUpGoal, KeepToPath
from can_seeker.control.safety_filter import SafetyFilter
from can_seeker.control.supervisor import State, Supervisor
from can_seeker.control.tick import Tick
from can_seeker.control.twist_limits import TwistLimits
from can_seeker.params import parse_topics


class ControllerParts:
    """Every part of the controller for ``config`` (the attributes of the controller's
    PARAMS)."""

    def __init__(self, config, camera_info_topic: str):
        self.wander = config.behaviour == 'wander'
        self.scan_sources = parse_topics(config.scan_topics)
        self.navigator = navigator = Navigator(
            config.grid_resolution, config.map_size, config.robot_radius, config.plan_margin,
            config.safety_margin, config.obstacle_memory, config.unknown_floor_wait)
        self.inputs = InputFreshness(config, self.scan_sources, self.wander, camera_info_topic)
        self.tracker = CanTracker(config, navigator)
        self.paths = paths = PathFollower(config, navigator)
        safety = SafetyFilter(config, navigator, bool(self.scan_sources))
        self.context = context = Context(config, navigator, self.tracker, self.inputs, safety,
                                         paths)
        self.bump = BumpRecovery(config.robot_radius, config.max_reverse)
        self.keep_to_path = KeepToPath(config, navigator, self.tracker, paths)
        self.back_up = BackUpToSeeFloor(config, navigator, safety, lambda: context.camera_view)
        self.explore = Explore(context)
        self.give_up = GiveUpGoal(navigator, self.explore)
        self.approach = Approach(context, self.keep_to_path)
        self.supervisor = Supervisor(
            {State.SEARCH: Search(context), State.EXPLORE: self.explore,
             State.APPROACH: self.approach, State.STOPPED: Stopped(context),
             State.LOST: Lost(context), State.WANDER: Wander(context),
             State.IDLE: Idle(context)},
            on_enter=(lambda _state: paths.clear(), self.back_up.reset, self.keep_to_path.reset,
                      self.give_up.reset))
        limits = TwistLimits(config.max_linear, config.max_reverse, config.max_angular,
                             config.max_linear_accel, config.max_angular_accel)
        self.tick = Tick(context, self.supervisor, self.bump, (self.back_up, TurnToLook(config)),
                         (self.give_up, self.keep_to_path), self.back_up, limits)
