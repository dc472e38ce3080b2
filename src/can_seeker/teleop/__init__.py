"""Driving by hand: keyboard key bindings and speeds, the raw terminal, the priority mux."""
