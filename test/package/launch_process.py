"""Stopping a roslaunch that a package test started in a session of its own."""
import os
import signal
import subprocess

SHUTDOWN_S = 30


def stop_launch(launch: subprocess.Popen) -> None:
    """SIGINT to the launch's process group, as Ctrl-C would; SIGKILL if it has not ended in
    :data:`SHUTDOWN_S`."""
    os.killpg(launch.pid, signal.SIGINT)
    try:
        launch.wait(SHUTDOWN_S)
    except subprocess.TimeoutExpired:
        os.killpg(launch.pid, signal.SIGKILL)
        launch.wait()
