"""The pybullet simulator: world building, drive limits, the sim-time loop, sim-thread calls."""
