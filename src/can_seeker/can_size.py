"""The can the nodes look for: a 330 ml soda can, as the simulator's. Its size and where its
colour begins are no parameters: the detector's size check, the range to its near surface and
the stop point are made for it."""

CAN_DIAMETER_M = 0.066
"""Diameter of the can (m)."""
CAN_HEIGHT_M = 0.122
"""Height of the can (m)."""
CAN_COLOUR_BOTTOM_M = 0.005
"""Height above the floor where the can's colour begins (m): a soda can's base is unprinted
metal for about 5 mm, so the floor range's ray through the red blob's lower edge meets the can
there, not on the floor (taken as floor, it put the can 4.5 % too far from a level camera 0.1 m
up)."""
