"""MP4 (H.264) from BGR frames, through the ffmpeg binary: plays in browsers and players,
which OpenCV's own mp4v writer does not guarantee."""
import shutil
import subprocess

import numpy as np


class Mp4Writer:
    """Frames of one size in, ``filename`` out; the size is fixed by the first frame."""

    def __init__(self, filename: str, fps: float):
        if shutil.which('ffmpeg') is None:
            raise RuntimeError('ffmpeg is not installed')
        self.filename = filename
        self.fps = fps
        self.size = None
        self.frames = 0
        self._process = None

    def write(self, frame: np.ndarray):
        """Append one HxWx3 uint8 BGR frame (W and H even)."""
        height, width = frame.shape[:2]
        if self._process is None:
            self.size = (width, height)
            self._process = subprocess.Popen(
                ['ffmpeg', '-y', '-loglevel', 'error', '-f', 'rawvideo', '-pix_fmt', 'bgr24',
                 '-s', '%dx%d' % self.size, '-r', '%g' % self.fps, '-i', '-',
                 '-c:v', 'libx264', '-pix_fmt', 'yuv420p', '-crf', '23', self.filename],
                stdin=subprocess.PIPE)
        if (width, height) != self.size:
            raise ValueError('frame is %dx%d, the video %dx%d' % ((width, height) + self.size))
        self._process.stdin.write(np.ascontiguousarray(frame, np.uint8).tobytes())
        self.frames += 1

    def close(self):
        """Finish the file; True when ffmpeg wrote it."""
        if self._process is None:
            return False
        self._process.stdin.close()
        return self._process.wait() == 0
