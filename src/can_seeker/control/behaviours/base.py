"""What every behaviour has: the shared :class:`Context`, the :class:`Result` of a tick, and
the no-op hooks of :class:`Behaviour`."""
from typing import NamedTuple, Optional

from can_seeker.control.input_freshness import problems_text
from can_seeker.control.reasons import Consequence, Kind, Reason, reason
from can_seeker.control.supervisor import Event
from can_seeker.control.twist_limits import Command


class Result(NamedTuple):
    """A behaviour's tick: its command (None: the next state's behaviour commands this tick)
    and the event it saw (None: none)."""

    command: Optional[Command]
    event: Optional[Event] = None


class Context:
    """What the behaviours share: ``config``, the ``navigator`` (map, pose, paths), the
    ``tracker`` (the can), the ``inputs`` (freshness), the ``safety`` filter, the ``paths``
    follower, the camera's ``camera_view``, the ``last_command`` sent and ``because``, the
    current tick's reasons."""

    def __init__(self, config, navigator, tracker, inputs, safety, paths):
        self.config = config
        self.navigator = navigator
        self.tracker = tracker
        self.inputs = inputs
        self.safety = safety
        self.paths = paths
        self.camera_view = None
        self.last_command: Command = (0.0, 0.0)
        self.because = None

    def can_navigate(self, now_s: float) -> bool:
        return self.inputs.can_navigate(now_s)

    def cannot_navigate(self, now_s: float, consequence: Consequence) -> Reason:
        """Why grid paths are out of reach (stale inputs, or no obstacle sensing at all)."""
        problems = (problems_text(self.inputs.sensing_problems(now_s))
                    if self.inputs.scan_sources else '')
        return reason(Kind.CANNOT_NAVIGATE, problems=problems, consequence=consequence)

    def turning(self) -> Command:
        """Turning in place at SEARCH_ANGULAR_RADPS toward the side the can was seen last."""
        return 0.0, self.tracker.turn_sign * self.config.search_angular


class Behaviour:
    """A state's behaviour. Hooks: :meth:`start` on entering the state, :meth:`on_pose` for
    odometry, :meth:`on_detection` for each detection, :meth:`expired` before a tick,
    :meth:`command` for the tick and :meth:`finished` with the tick's final command."""

    def __init__(self, context: Context):
        self.context = context
        self.config = context.config

    def start(self, now_s: float) -> None:
        """The state was entered at ``now_s``: begin its memory afresh."""

    def on_pose(self, previous, pose) -> None:
        """The robot moved from ``previous`` to ``pose`` (odom)."""

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        """A detection came; ``ranged``: it ranged the can (or the can is carried)."""
        return None

    def expired(self, now_s: float) -> Optional[Event]:
        """An event of time passing, before the tick at ``now_s``."""
        return None

    def command(self, now_s: float) -> Result:
        raise NotImplementedError

    def finished(self, command: Command, now_s: float) -> Optional[Event]:
        """The tick ended in ``command`` (after limits and safety)."""
        return None

