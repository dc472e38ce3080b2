"""MP4 writing through ffmpeg."""
import subprocess

import numpy as np
import pytest

from can_seeker.evaluation.video import Mp4Writer


def test_writes_a_playable_mp4_with_every_frame(tmp_path):
    filename = str(tmp_path / 'clip.mp4')
    writer = Mp4Writer(filename, 15.0)
    for index in range(12):
        writer.write(np.full((48, 64, 3), index * 20, np.uint8))
    assert writer.close()
    probe = subprocess.run(['ffprobe', '-v', 'error', '-count_frames', '-select_streams', 'v:0',
                            '-show_entries', 'stream=codec_name,width,height,nb_read_frames',
                            '-of', 'csv=p=0', filename], capture_output=True, text=True)
    assert probe.stdout.strip() == 'h264,64,48,12'


def test_rejects_a_frame_of_another_size(tmp_path):
    writer = Mp4Writer(str(tmp_path / 'clip.mp4'), 10.0)
    writer.write(np.zeros((48, 64, 3), np.uint8))
    with pytest.raises(ValueError):
        writer.write(np.zeros((50, 64, 3), np.uint8))
    writer.close()


def test_nothing_written_is_reported(tmp_path):
    assert not Mp4Writer(str(tmp_path / 'clip.mp4'), 10.0).close()
