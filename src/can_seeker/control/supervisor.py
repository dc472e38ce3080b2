"""The controller's states and THE transition table (state x event -> state); the
:class:`Supervisor` is the only place the state changes.

Behaviours and the controller report :class:`Event` s; the supervisor looks each one up in
:data:`TRANSITIONS` and starts the next state's behaviour afresh (and tells the recoveries,
whose memory may span states). An event a state has no row for is a programming error.
"""
import enum
from typing import Callable, Dict, Iterable, Mapping, Tuple

from can_seeker.control.tuning import LOST_TIMEOUT_S, VANISH_TIMEOUT_S


class State(enum.Enum):
    """Controller states, published by name on ``~state``."""

    SEARCH = 'SEARCH'
    EXPLORE = 'EXPLORE'
    APPROACH = 'APPROACH'
    STOPPED = 'STOPPED'
    LOST = 'LOST'
    WANDER = 'WANDER'
    IDLE = 'IDLE'


class Event(enum.Enum):
    """What happened, as far as the state is concerned."""

    RESET_DISARMED = 'reset while disarmed'
    RESET_SEEK = 'reset, armed to seek'
    RESET_WANDER = 'reset, armed to wander'
    CAN_RANGED = 'the can was ranged'
    CAN_OUT_OF_RANGE = 'the can was not ranged'
    CAN_VANISHED = 'the can was not ranged for %g s' % VANISH_TIMEOUT_S
    CAN_MOVED = 'the can is off the stop point by more than the reapproach tolerances'
    SETTLED = 'within both tolerances and at rest'
    ARRIVED_UNSEEN = ('at rest where the can was ranged last, which the camera would see but '
                      'has not ranged for %g s' % VANISH_TIMEOUT_S)
    LOST_TIMEOUT = "%g s in LOST without getting nearer the can's last place" % LOST_TIMEOUT_S
    CAN_NOT_THERE = 'facing where the can was seen last, it is not there'
    SEARCHED_ALL_ROUND = 'a full turn without the can, exploring allowed'
    GOAL_REACHED = 'at the exploration goal'
    NOTHING_TO_EXPLORE = 'no goal left to explore'


_RESETS = {Event.RESET_DISARMED: State.IDLE, Event.RESET_SEEK: State.SEARCH,
           Event.RESET_WANDER: State.WANDER}

TRANSITIONS: Mapping[Tuple[State, Event], State] = {
    **{(state, event): target for state in State for event, target in _RESETS.items()},
    (State.SEARCH, Event.CAN_RANGED): State.APPROACH,
    (State.SEARCH, Event.SEARCHED_ALL_ROUND): State.EXPLORE,
    (State.EXPLORE, Event.CAN_RANGED): State.APPROACH,
    (State.EXPLORE, Event.GOAL_REACHED): State.SEARCH,
    (State.EXPLORE, Event.NOTHING_TO_EXPLORE): State.SEARCH,
    (State.APPROACH, Event.CAN_OUT_OF_RANGE): State.LOST,
    (State.APPROACH, Event.SETTLED): State.STOPPED,
    (State.APPROACH, Event.ARRIVED_UNSEEN): State.LOST,
    (State.STOPPED, Event.CAN_MOVED): State.APPROACH,
    (State.STOPPED, Event.CAN_VANISHED): State.LOST,
    (State.LOST, Event.CAN_RANGED): State.APPROACH,
    (State.LOST, Event.LOST_TIMEOUT): State.SEARCH,
    (State.LOST, Event.CAN_NOT_THERE): State.SEARCH,
}
"""Every state change: (state, event) -> next state."""


class Supervisor:
    """Holds the state and its behaviour; :meth:`handle` applies an event through the table.

    ``behaviours`` maps each state to its behaviour (``start(now_s)`` begins its memory
    afresh); ``on_enter(state)`` runs after every change (recoveries, the shared path).
    """

    def __init__(self, behaviours: Mapping[State, object],
                 on_enter: Iterable[Callable[[State], None]]):
        self.behaviours: Dict[State, object] = dict(behaviours)
        self.on_enter = tuple(on_enter)
        self.state = State.IDLE

    @property
    def behaviour(self):
        """The running state's behaviour."""
        return self.behaviours[self.state]

    def handle(self, event, now_s: float) -> None:
        """Apply ``event`` (None: nothing happened) at ``now_s``."""
        if event is None:
            return
        self.state = TRANSITIONS[(self.state, event)]
        for hook in self.on_enter:
            hook(self.state)
        self.behaviour.start(now_s)
