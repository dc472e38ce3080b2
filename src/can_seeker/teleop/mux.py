"""Priority multiplexer of velocity commands, like twist_mux: the highest-priority input that
is still fresh drives the robot.

Each input has a topic, a priority and a timeout. A message is forwarded when no input of a
higher priority has sent one within its timeout; a stale input gives way to the next one at
that input's next message. When every input has gone stale, one zero command is due (the base
must not keep executing the last command of a dead publisher).
"""
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

from can_seeker.params import Param

PARAMS = (
    Param('inputs', 'cmd_vel_teleop:100:0.5 cmd_vel_auto:10:0.5',
          'command inputs, space-separated topic:priority:timeout_s; the highest priority '
          'input heard within its timeout wins (topics are remappable names)'),
    Param('rate', 20.0, 'rate at which stale inputs are checked for the zero command (Hz)',
          1.0, 200.0),
)


@dataclass(frozen=True)
class MuxInput:
    """One command source: topic name, priority (higher wins), timeout (s)."""

    topic: str
    priority: int
    timeout_s: float


def parse_inputs(text: str) -> Tuple[MuxInput, ...]:
    """``topic:priority:timeout_s`` entries separated by spaces; ValueError says what is wrong."""
    inputs = []
    for entry in text.split():
        parts = entry.split(':')
        if len(parts) != 3 or not parts[0]:
            raise ValueError('input %r is not topic:priority:timeout_s' % entry)
        try:
            priority, timeout_s = int(parts[1]), float(parts[2])
        except ValueError:
            raise ValueError('input %r: priority must be a whole number and timeout_s a number'
                             % entry)
        if not timeout_s > 0.0 or timeout_s == float('inf'):
            raise ValueError('input %r: timeout_s must be positive and finite' % entry)
        inputs.append(MuxInput(parts[0], priority, timeout_s))
    if not inputs:
        raise ValueError('no inputs')
    topics = [entry.topic for entry in inputs]
    if len(set(topics)) != len(topics):
        raise ValueError('an input topic is listed twice: %s' % ' '.join(topics))
    return tuple(inputs)


class TwistMux:
    """Decides which input's messages reach the output; times in seconds on one clock."""

    def __init__(self, inputs: Sequence[MuxInput]):
        self.inputs = tuple(inputs)
        self._heard_s: List[Optional[float]] = [None] * len(self.inputs)
        self._zero_sent = True

    def _fresh(self, index: int, now_s: float) -> bool:
        heard = self._heard_s[index]
        return heard is not None and 0.0 <= now_s - heard <= self.inputs[index].timeout_s

    def active(self, now_s: float) -> Optional[MuxInput]:
        """The fresh input with the highest priority (the first listed on a tie), or None."""
        fresh = [entry for index, entry in enumerate(self.inputs) if self._fresh(index, now_s)]
        return max(fresh, key=lambda entry: entry.priority) if fresh else None

    def offer(self, index: int, now_s: float) -> bool:
        """A message arrived on input ``index`` at ``now_s``: True when it is to be forwarded."""
        self._heard_s[index] = now_s
        forward = all(not self._fresh(other, now_s)
                      or self.inputs[other].priority <= self.inputs[index].priority
                      for other in range(len(self.inputs)))
        if forward:
            self._zero_sent = False
        return forward

    def zero_due(self, now_s: float) -> bool:
        """True once each time every input has gone stale after something was forwarded."""
        if self._zero_sent or self.active(now_s) is not None:
            return False
        self._zero_sent = True
        return True
