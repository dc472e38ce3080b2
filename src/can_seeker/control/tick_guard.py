"""Control ticks that always end in a command.

rospy ends a Timer's thread at the first exception its callback raises, and a subscriber
callback that raises sends nothing: either way the robot would keep executing its last
command. Each tick runs through :class:`TickGuard`: when anything in it fails, the zero command
is sent and the error logged, throttled per kind of error, with its traceback the first time
that kind occurs.
"""
import traceback
from typing import Callable, Set

from can_seeker.throttle import KindThrottle

LOG_PERIOD_S = 5.0


class TickGuard:
    """Runs ticks; logs their failures through ``log_error`` at most once per ``period_s``
    per kind of error."""

    def __init__(self, log_error: Callable[[str], None], period_s: float = LOG_PERIOD_S):
        self._log_error = log_error
        self._throttle = KindThrottle(period_s)
        self._traced: Set[str] = set()

    def run(self, tick: Callable[[], None], send_zero: Callable[[], None], now_s: float) -> None:
        """Run ``tick`` (which sends its command); if it raises, ``send_zero()`` instead."""
        try:
            tick()
            return
        except Exception as error:  # whatever failed, the robot must not keep its command
            self._report('control tick failed, sending zero', error, now_s)
        try:
            send_zero()
        except Exception as error:  # nothing more can be sent; the next tick tries again
            self._report('could not send the zero command', error, now_s)

    def _report(self, what: str, error: Exception, now_s: float) -> None:
        kind = '%s: %s' % (what, type(error).__name__)
        allowed, held_back = self._throttle.allow(kind, now_s)
        if not allowed:
            return
        message = '%s: %s: %s' % (what, type(error).__name__, error)
        if held_back:
            message += ' (%d more since the last report)' % held_back
        if kind not in self._traced:
            self._traced.add(kind)
            message += '\n' + ''.join(traceback.format_exception(type(error), error,
                                                                 error.__traceback__))
        self._log_error(message)
