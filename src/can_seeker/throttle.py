"""Log throttling per kind of fault: one message per kind and period, however its text varies.

rospy throttles per call site (all faults share one budget, so a rare fault hides behind a
frequent one) or per identical text (frames cut to ever different lengths log one line each).
A node names the kind of each fault and asks :class:`KindThrottle` whether to log it.
"""
from typing import Dict, Tuple


class KindThrottle:
    """Allows the first message of each kind, then at most one per ``period_s`` per kind."""

    def __init__(self, period_s: float):
        self.period_s = period_s
        self._last: Dict[str, Tuple[float, int]] = {}

    def allow(self, kind: str, now_s: float) -> Tuple[bool, int]:
        """(log it?, how many messages of this kind were held back since the last one logged)."""
        last = self._last.get(kind)
        if last is not None and now_s - last[0] < self.period_s:
            self._last[kind] = (last[0], last[1] + 1)
            return False, 0
        held_back = last[1] if last is not None else 0
        self._last[kind] = (now_s, 0)
        return True, held_back
