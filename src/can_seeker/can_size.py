"""The can the nodes look for: a 330 ml soda can, as the simulator's. Its size is no parameter:
the detector's size check, the range to its near surface and the stop point are made for it."""

CAN_DIAMETER_M = 0.066
"""Diameter of the can (m)."""
CAN_HEIGHT_M = 0.122
"""Height of the can (m)."""
