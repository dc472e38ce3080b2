"""Can a window be opened? Asked in a child process, because the toolkits kill the process that
fails: Qt aborts (SIGABRT) and pybullet's GUI exits when the X display cannot be opened."""
import os
import subprocess
import sys
from typing import Mapping, Optional

OPENCV_WINDOW_PROBE = ('import cv2\n'
                       'cv2.namedWindow("can_seeker display check")\n'
                       'cv2.destroyAllWindows()\n')
"""OpenCV's own GUI backend (Qt or GTK) opening and closing a window."""

X11_PROBE = ('import ctypes, ctypes.util, sys\n'
             'name = ctypes.util.find_library("X11")\n'
             'if not name: sys.exit("libX11 is not installed")\n'
             'x11 = ctypes.cdll.LoadLibrary(name)\n'
             'x11.XOpenDisplay.restype = ctypes.c_void_p\n'
             'x11.XCloseDisplay.argtypes = [ctypes.c_void_p]\n'
             'display = x11.XOpenDisplay(None)\n'
             'if not display: sys.exit("XOpenDisplay failed")\n'
             'x11.XCloseDisplay(display)\n')
"""A connection to the X display, as pybullet's GUI makes it (libX11)."""

PROBE_TIMEOUT_S = 20.0


def display_problem(probe_code: str, environ: Optional[Mapping[str, str]] = None,
                    timeout_s: float = PROBE_TIMEOUT_S) -> Optional[str]:
    """None when ``probe_code`` runs cleanly in a child Python on this display, else why not."""
    environ = os.environ if environ is None else environ
    display = environ.get('DISPLAY', '')
    if not display:
        return 'DISPLAY is not set'
    try:
        probe = subprocess.run([sys.executable, '-c', probe_code], env=dict(environ),
                               stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, timeout=timeout_s, check=False)
    except subprocess.TimeoutExpired:
        return 'opening a window on DISPLAY=%s took over %.0f s' % (display, timeout_s)
    if probe.returncode == 0:
        return None
    lines = [line.strip() for line in probe.stderr.decode('utf-8', 'replace').splitlines()
             if line.strip()]
    detail = next((line for line in lines if 'display' in line.lower()),
                  lines[-1] if lines else 'exit status %d' % probe.returncode)
    return 'cannot open a window on DISPLAY=%s: %s' % (display, detail)
