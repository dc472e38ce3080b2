"""The can_stopper controller: a supervisor over a behaviour per state and recoveries, the
safety filter, the map and paths, velocity and acceleration limits."""
