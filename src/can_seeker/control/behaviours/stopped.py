"""STOPPED: hold zero in front of the can; approach again when it moved, LOST when it
vanished for VANISH_TIMEOUT_S."""
import math
from typing import Optional

from can_seeker.control.behaviours.base import Behaviour, Result
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.reasons import Kind, reason
from can_seeker.control.supervisor import Event


class Stopped(Behaviour):
    """Remembers since when the can was last ranged."""

    def start(self, now_s: float) -> None:
        self.seen_since_s = now_s

    def on_detection(self, ranged: bool, now_s: float) -> Optional[Event]:
        config = self.config
        if not ranged:
            if elapsed_s(now_s, self.seen_since_s) > config.vanish_timeout:
                return Event.CAN_VANISHED
            return None
        self.seen_since_s = now_s
        gap_error, bearing = self.context.tracker.errors()
        if (abs(gap_error) > config.reapproach_distance
                or abs(bearing) > math.radians(config.reapproach_bearing_deg)):
            return Event.CAN_MOVED
        return None

    def command(self, now_s: float) -> Result:
        self.context.because(reason(Kind.STOPPED_AT_CAN))
        return Result((0.0, 0.0))
