"""The can_stopper behaviour: state machine and control law, velocity and acceleration limits."""
