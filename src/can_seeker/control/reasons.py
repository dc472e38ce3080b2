"""Why a command is zero or limited: a :class:`Reason` is a kind with its data; its text is
made here, in one place, for the diagnostics (``Controller.why``). Tests assert on the kind and
the data, never on the wording.

:class:`Because` collects a tick's reasons: the first one found stands.
"""
import enum
import math
from dataclasses import dataclass
from typing import Any, Callable, Dict, Optional, Tuple


class Kind(enum.Enum):
    """What made a command zero or limited; each kind's data is listed beside it."""

    DISARMED = 'disarmed'                          # arm_hint
    INPUTS_MISSING = 'inputs missing'              # problems (text of the missing inputs)
    TICK_FAILED = 'tick failed'                    # error type name, message
    BUMPED = 'bumped'                              # backed_m, back_off_m
    EXPLORE_OFF = 'explore off'                    # -
    CANNOT_NAVIGATE = 'cannot navigate'            # problems ('' without sensing), consequence
    STOPPED_AT_CAN = 'stopped at the can'          # -
    SENSING_STALE = 'sensing stale'                # problems
    BACKING_TO_SEE = 'backing up to see'           # backed_m, total_m
    SPEED_CAPPED = 'speed capped'                  # unknown_floor, ahead, free_m, speed, then
    TOO_CLOSE = 'too close'                        # gap_m
    CAN_NOT_THERE = 'can not there'                # -
    ARRIVED_UNSEEN = 'arrived, can unseen'         # unseen_s
    TURNING_TO_LAST_SEEN = 'turning to last seen'  # -
    FACING_LAST_SEEN = 'facing last seen'          # -
    APPROACH_STALLED = 'approach stalled'          # nearer_m, stall_s, keep_to_path
    NO_CLEAR_HEADING = 'no clear heading'          # clear_m
    TURNING_TO_PATH = 'turning to the path'        # heading_deg, limit_deg
    NO_PATH_TO_GOAL = 'no path to goal'            # -
    NO_PATH_TO_CAN = 'no path to the can'          # -
    DEADBAND = 'deadband'                          # gap_error_m, bearing_rad
    TURNING_TO_CAN = 'turning to the can'          # bearing_rad, turn_in_place_deg
    TURNING_TO_STOP_ASIDE = 'turning to a stop point aside'  # bearing_rad


class Then(enum.Enum):
    """What a robot capped at unknown floor does about it (:data:`Kind.SPEED_CAPPED`)."""

    WAIT = ''
    BACK_UP = ', below the camera\'s view: backing up to see it'
    LOOK = ', turning to look at it'


class Consequence(enum.Enum):
    """What a robot that cannot drive on grid paths does instead (:data:`Kind.CANNOT_NAVIGATE`)."""

    SEARCH_ON = 'searched a full turn, cannot explore'
    NO_EXPLORING = 'cannot explore'
    TURN_TO_LAST_SEEN = 'turning toward where the can was seen'


@dataclass(frozen=True)
class Reason:
    """One reason: its :class:`Kind` and that kind's data, by name."""

    kind: Kind
    data: Tuple[Tuple[str, Any], ...] = ()

    def __getitem__(self, name: str) -> Any:
        return dict(self.data)[name]

    @property
    def text(self) -> str:
        """The sentence the diagnostics show."""
        return _TEXT[self.kind](dict(self.data))


def reason(kind: Kind, **data) -> Reason:
    """A :class:`Reason` of ``kind`` with ``data``."""
    return Reason(kind, tuple(data.items()))


def _speed_capped(d: Dict[str, Any]) -> str:
    return ('%s %s: %.2f m of free travel, speed capped at %.2f m/s%s'
            % ('floor not yet seen' if d['unknown_floor'] else 'obstacle',
               'ahead' if d['ahead'] else 'behind', d['free_m'], d['speed'], d['then'].value))


def _stalled(d: Dict[str, Any]) -> str:
    return 'no %.1f m nearer to the can in %.0f s: %s' % (
        d['nearer_m'], d['stall_s'], 'keeping to a path to it' if d['keep_to_path'] else
        'taking the direct way again where the straight line is clear')


_TEXT: Dict[Kind, Callable[[Dict[str, Any]], str]] = {
    Kind.DISARMED: lambda d: 'disarmed (to arm: %s)' % d['arm_hint'],
    Kind.INPUTS_MISSING: lambda d: d['problems'],
    Kind.TICK_FAILED: lambda d: 'control tick failed (%s: %s)' % (d['error'], d['message']),
    Kind.BUMPED: lambda d: 'bumped into something: backing off %.2f of %.2f m' % (
        d['backed_m'], d['back_off_m']),
    Kind.EXPLORE_OFF: lambda d: 'searched a full turn, ~explore is false: turning on in place',
    Kind.CANNOT_NAVIGATE: lambda d: '%s: %s' % (
        d['problems'] or 'no obstacle sensing (no scan topics)', d['consequence'].value),
    Kind.STOPPED_AT_CAN: lambda d: 'stopped at the can',
    Kind.SENSING_STALE: lambda d: '%s: no driving, only turning' % d['problems'],
    Kind.BACKING_TO_SEE: lambda d: ('floor below the camera\'s view ahead: backing up %.2f of '
                                    '%.2f m to see it' % (d['backed_m'], d['total_m'])),
    Kind.SPEED_CAPPED: _speed_capped,
    Kind.TOO_CLOSE: lambda d: 'closer than stop_distance (gap %.3f m): no driving forward' % (
        d['gap_m']),
    Kind.CAN_NOT_THERE: lambda d: 'the can is not where it was seen last: searching',
    Kind.ARRIVED_UNSEEN: lambda d: ('arrived where the can was ranged last, but the camera has '
                                    'not seen it there for %.1f s: LOST' % d['unseen_s']),
    Kind.TURNING_TO_LAST_SEEN: lambda d: 'turning toward where the can was seen last',
    Kind.FACING_LAST_SEEN: lambda d: 'facing where the can was seen last, it is not in view',
    Kind.APPROACH_STALLED: _stalled,
    Kind.NO_CLEAR_HEADING: lambda d: 'no heading clear for %.2f m: turning in place toward the '
                                     'path' % d['clear_m'],
    Kind.TURNING_TO_PATH: lambda d: ('turning to the path first: clear heading %.0f deg off, '
                                     'driving within %.0f deg' % (d['heading_deg'],
                                                                  d['limit_deg'])),
    Kind.NO_PATH_TO_GOAL: lambda d: 'no path to the exploration goal: choosing another',
    Kind.NO_PATH_TO_CAN: lambda d: ('keeping to a path to the can, none found: backing up to '
                                    'see the way'),
    Kind.DEADBAND: lambda d: ('deadband: gap within %.1f mm of stop_distance, bearing %.2f deg'
                              % (1000.0 * abs(d['gap_error_m']), math.degrees(d['bearing_rad']))),
    Kind.TURNING_TO_CAN: lambda d: ('turning to the can first: bearing %.1f deg, driving within '
                                    '%.1f deg' % (math.degrees(d['bearing_rad']),
                                                  d['turn_in_place_deg'])),
    Kind.TURNING_TO_STOP_ASIDE: lambda d: ('an obstacle holds the straight approach back: '
                                           'turning to a stop point beside it, %.0f deg off'
                                           % math.degrees(d['bearing_rad'])),
}


class Because:
    """The reasons of one tick: the first one given stands (later ones are less direct)."""

    def __init__(self):
        self.first: Optional[Reason] = None

    def __call__(self, found: Optional[Reason]) -> None:
        if self.first is None and found is not None:
            self.first = found

    def state_changed(self, found: Reason) -> None:
        """A state change's reason: it replaces the tick's (the change is the news)."""
        self.first = found
