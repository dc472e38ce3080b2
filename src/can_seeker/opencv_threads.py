"""OpenCV's worker threads in the nodes that handle one camera frame at a time."""
import cv2

OPENCV_THREADS = 1
"""OpenCV worker threads: one frame's passes are too short to share (tens of microseconds at
640x480), and idle TBB workers spin after each one; a single thread costs about 0.2 ms less CPU
per frame in image_converter and about 0.6 ms in obstacle_scan (5 %), the same results."""


def use_one_opencv_thread() -> None:
    """Run OpenCV's passes on the calling thread only (call once, before the first frame)."""
    cv2.setNumThreads(OPENCV_THREADS)
