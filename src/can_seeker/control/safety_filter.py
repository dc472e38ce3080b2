"""The safety layer, stateless: a command and the obstacle map in, the command with its speed
capped (forward or backward) to what the sensed obstacles and unknown floor allow along its arc
out, with the :class:`~can_seeker.control.reasons.Reason` when it was capped. Turning in place
is never limited: the robot is round. Stale sensing allows turning only.
"""
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

from can_seeker.control import avoidance
from can_seeker.control.input_freshness import MissingInput, problems_text
from can_seeker.control.reasons import Kind, Reason, Then, reason
from can_seeker.control.twist_limits import Command

SAFETY_RESERVE_M = 0.03
"""Braking at ~max_linear_accel stops the robot this much short of the free travel (m)."""


class Verdict(NamedTuple):
    """The safe speed (m/s) of a command, the free travel (m) along its arc and, when unknown
    floor limits it, the nearest unknown point (base_link); ``capped`` when it is slower than
    the command."""

    linear: float
    free_m: float
    unknown_point: Optional[np.ndarray]
    capped: bool


class SafetyFilter:
    """Caps commands by the navigator's obstacle map (``CAN_EXCLUSION_RADIUS_M`` about
    ``exclude_xy``, the target can, is no obstacle)."""

    def __init__(self, config, navigator, senses_obstacles: bool):
        self.config = config
        self.navigator = navigator
        self.senses_obstacles = senses_obstacles

    def applies(self, command: Command) -> bool:
        """True when the command moves the robot and obstacle sensing is on."""
        return self.senses_obstacles and command[0] != 0.0

    def check(self, command: Command, exclude_xy) -> Verdict:
        """The safe speed of ``command`` along its arc."""
        linear = command[0]
        free_m, unknown_point = self.navigator.safety_block(command, exclude_xy,
                                                            self.config.can_exclusion_radius)
        safe = avoidance.safe_linear(linear, free_m, self.config.max_linear_accel,
                                     SAFETY_RESERVE_M)
        return Verdict(safe, free_m, unknown_point, abs(safe) < abs(linear))

    @staticmethod
    def capped_reason(command: Command, verdict: Verdict, then: Then = Then.WAIT) -> Reason:
        """Why ``verdict`` capped ``command`` (and what the robot does about it)."""
        return reason(Kind.SPEED_CAPPED, unknown_floor=verdict.unknown_point is not None,
                      ahead=command[0] > 0.0, free_m=verdict.free_m, speed=abs(verdict.linear),
                      then=then)

    @staticmethod
    def turning_only(command: Command, problems: Sequence[MissingInput]) -> Tuple[Command,
                                                                                   Reason]:
        """Stale sensing: the command's turn, no driving."""
        return (0.0, command[1]), reason(Kind.SENSING_STALE, problems=problems_text(problems))

    def filter(self, command: Command, problems: Sequence[MissingInput],
               exclude_xy) -> Tuple[Command, Optional[Reason]]:
        """``command`` capped (turning only with ``problems``, the stale sensing inputs), and
        why, or None when it passes as it is."""
        if not self.applies(command):
            return command, None
        if problems:
            return self.turning_only(command, problems)
        verdict = self.check(command, exclude_xy)
        if not verdict.capped:
            return (verdict.linear, command[1]), None
        return (verdict.linear, command[1]), self.capped_reason(command, verdict)

    def can_back_up(self, exclude_xy) -> bool:
        """True when the robot may back up at ~max_reverse."""
        reverse = (-self.config.max_reverse, 0.0)
        return self.check(reverse, exclude_xy).linear != 0.0
