"""When a node that looks up its sensors' mounts in TF needs /tf at all.

A mount on a fixed joint is on /tf_static; /tf carries what moves (the robot's odometry
transform at tens of Hz, a pan-tilt joint). A node whose every lookup resolves from /tf_static
alone gains nothing from /tf but the cost of receiving each message (:class:`TfDemand`).
"""
from typing import Hashable, Set


class TfDemand:
    """Whether a node needs /tf for its lookups: until a lookup first resolved from /tf_static
    alone, and while the last lookup of any (target, source) pair did not (a frame on a moving
    joint, or a mount that is not on /tf_static yet)."""

    def __init__(self):
        self.dynamic_pairs: Set[Hashable] = set()
        self.resolved_static = False

    def looked_up(self, pair: Hashable, from_static: bool) -> None:
        """Note how the lookup of ``pair`` resolved: from /tf_static alone, or not."""
        if from_static:
            self.resolved_static = True
            self.dynamic_pairs.discard(pair)
        else:
            self.dynamic_pairs.add(pair)

    @property
    def needs_tf(self) -> bool:
        return not self.resolved_static or bool(self.dynamic_pairs)

