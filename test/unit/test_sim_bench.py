"""The world benchmark runs the requested configuration and reports consistent numbers."""
import pathlib

from can_seeker.evaluation.sim_bench import run_case

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')


def test_run_case_counts_frames_and_time():
    result = run_case(URDF, 'tiny', 64, 48, 15.0, 0.5)
    assert result['renderer'] == 'tiny'
    assert result['frames'] == 7
    assert result['real_time_factor'] > 0.0
    assert abs(result['real_time_factor'] * result['wall_s'] - 0.5) < 1e-9
    assert result['step_us'] > 0.0



def test_run_case_in_a_room_with_the_textured_can():
    result = run_case(URDF, 'tiny', 64, 48, 15.0, 0.5, 'room', 'textured')
    assert result['frames'] == 7
    assert result['real_time_factor'] > 0.0
