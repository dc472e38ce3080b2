"""Telling a dead simulator from a slow one by its clock (pure, no ROS)."""


class ClockWatch:
    """Watches a sim clock against wall time. A running simulator's clock moves (in lockstep a
    frame nobody answers still steps on after the gate's time-out, 2 s by default), so a clock
    that has stood still for ``stall_wall_s`` of wall time belongs to a simulator that died
    or hung, and a wait for sim time would never end."""

    def __init__(self, stall_wall_s: float, sim_s: float, wall_s: float):
        self.stall_wall_s = stall_wall_s
        self.sim_s = sim_s
        self.moved_wall_s = wall_s

    def stalled(self, sim_s: float, wall_s: float) -> bool:
        """True when the clock reads ``sim_s`` at ``wall_s`` and has not moved for longer than
        ``stall_wall_s``."""
        if sim_s != self.sim_s:
            self.sim_s, self.moved_wall_s = sim_s, wall_s
            return False
        return wall_s - self.moved_wall_s > self.stall_wall_s
