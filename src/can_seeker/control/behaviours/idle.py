"""IDLE: disarmed, every command zero."""
from can_seeker.control.behaviours.base import Behaviour, Result


class Idle(Behaviour):
    """Commands zero (the controller sends zero before asking while disarmed)."""

    def command(self, now_s: float) -> Result:
        return Result((0.0, 0.0))
