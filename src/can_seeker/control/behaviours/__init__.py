"""The controller's behaviours, one per state; each owns its per-state memory."""
