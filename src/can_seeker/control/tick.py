"""One control tick, in order: input freshness -> supervisor (time-outs) -> behaviour (or the
bump recovery) -> floor recoveries around the safety filter's verdict -> twist limits -> the
safety filter on the limited command -> stall watchdogs -> never forward closer than
~stop_distance -> the supervisor (settled).

The safety filter checks the behaviour's command (the floor recoveries act on its verdict) and,
as the last word, the command the twist limits ramped toward it.
"""
from typing import Optional, Sequence, Tuple

from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.input_freshness import problems_text
from can_seeker.control.reasons import Because, Kind, Reason, Then, reason
from can_seeker.control.supervisor import State
from can_seeker.control.twist_limits import ZERO, Command, limit_twist, require_finite


class Tick:
    """Runs ticks over the controller's parts; remembers when the last command was made."""

    def __init__(self, context, supervisor, bump, unblockers: Sequence, watchdogs: Sequence,
                 back_up, limits):
        self.context = context
        self.supervisor = supervisor
        self.bump = bump
        self.unblockers = tuple(unblockers)
        self.watchdogs = tuple(watchdogs)
        self.back_up = back_up
        self.limits = limits
        self.reset()

    def reset(self) -> None:
        """At rest, no command made yet."""
        self.context.last_command = ZERO
        self.last_command_s: Optional[float] = None

    def exclude_xy(self):
        """The can, no obstacle to the safety filter while APPROACH or LOST head for it."""
        if self.supervisor.state in (State.APPROACH, State.LOST):
            return self.context.tracker.can_xy
        return None

    def run(self, now_s: float, disarmed: Optional[Reason]) -> Tuple[Command, Optional[Reason]]:
        """The command at ``now_s`` and why it is zero or limited (``disarmed``: why it is
        disarmed, None while armed)."""
        context, supervisor = self.context, self.supervisor
        dt_s = 0.0 if self.last_command_s is None else elapsed_s(now_s, self.last_command_s)
        self.last_command_s = now_s
        if disarmed is not None or context.inputs.is_stale(now_s):
            # A disarm is an emergency stop: zero at once, not a ramp-down within the
            # acceleration limits that would keep the robot driving after it was told to stop.
            context.last_command = ZERO
            return ZERO, disarmed or reason(
                Kind.INPUTS_MISSING, problems=problems_text(context.inputs.missing_inputs(now_s)))
        because = context.because = Because()
        supervisor.handle(supervisor.behaviour.expired(now_s), now_s)
        recovery = self.bump.command(context.navigator.pose, now_s)
        if recovery is not None:
            desired, why = recovery
            because(why)
            context.paths.clear()
        else:
            desired = self._recover(self._behaviour_command(now_s), now_s)
        limited = limit_twist(context.last_command, desired, dt_s, self.limits)
        (linear, angular), why = context.safety.filter(
            limited, context.inputs.sensing_problems(now_s), self.exclude_xy())
        because(why)
        for watchdog in self.watchdogs:
            watchdog.after_tick(supervisor.state, now_s, because)
        sighting = context.tracker.sighting
        if (supervisor.state is not State.WANDER and sighting is not None
                and sighting.has_range and linear > 0.0
                and sighting.gap_m < context.config.stop_distance):
            linear = 0.0
            because(reason(Kind.TOO_CLOSE, gap_m=sighting.gap_m))
        context.last_command = (linear, angular)
        supervisor.handle(supervisor.behaviour.finished(context.last_command, now_s), now_s)
        return context.last_command, because.first

    def _behaviour_command(self, now_s: float) -> Command:
        """The running behaviour's command; one that hands over (SEARCH to EXPLORE) leaves
        the tick to the next state's behaviour."""
        supervisor = self.supervisor
        result = supervisor.behaviour.command(now_s)
        supervisor.handle(result.event, now_s)
        if result.command is None:
            result = supervisor.behaviour.command(now_s)
            supervisor.handle(result.event, now_s)
        return require_finite(result.command, '%s command' % supervisor.state.value)

    def _recover(self, command: Command, now_s: float) -> Command:
        """The behaviour's command through the safety filter, with the floor recoveries: a
        back-up under way goes on; a robot that unknown floor keeps from driving forward tries
        each of ``unblockers`` in order."""
        context = self.context
        safety, because = context.safety, context.because
        if command[0] <= 0.0:
            self.back_up.reset()
        if not safety.applies(command):
            return command
        problems = context.inputs.sensing_problems(now_s)
        if problems:
            command, why = safety.turning_only(command, problems)
            because(why)
            return command
        exclude_xy = self.exclude_xy()
        resumed = self.back_up.resume(exclude_xy)
        if resumed is not None:
            because(resumed[1])
            return resumed[0]
        verdict = safety.check(command, exclude_xy)
        if not verdict.capped:
            return verdict.linear, command[1]
        result = (verdict.linear, command[1]), Then.WAIT
        if verdict.unknown_point is not None and verdict.linear == 0.0 and command[0] > 0.0:
            for unblocker in self.unblockers:
                found = unblocker.unblock(command, verdict, exclude_xy)
                if found is not None:
                    result = found
                    break
        because(safety.capped_reason(command, verdict, result[1]))
        return result[0]
