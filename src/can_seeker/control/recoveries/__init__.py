"""Recoveries: what the controller tries, in order, when progress stops."""
