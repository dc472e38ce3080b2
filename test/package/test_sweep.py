"""``evaluate --sweep`` end to end: a sweep of can_stopper's ~stop_distance over two values, 10
seeds each, on a local cluster of two worker processes (empty world, can 0.8-1.5 m away,
lockstep). Its table, JSON record and plot are written; both settings ran the same seeds; the
robot stopped at each setting's own distance (the true final gaps of the two settings differ by
the 0.2 m between them), and the table's success counts are the record's.
"""
import json
import os
import struct
import subprocess
import sys

import pytest

VALUES = ('0.3', '0.5')
SEED = 0
TRIALS = 10
TIMEOUT_S = 900.0
GAP_TOLERANCE_M = 0.02
"""The evaluation's own success band: |true gap - stop distance|."""
PLOT_SIZE_PX = (1260, 324)
"""sweep.png: four panels of 14 x 3.6 inches at 90 dpi."""


def png_size(path):
    """(width, height) from a PNG's header; AssertionError if it is no PNG."""
    with open(path, 'rb') as image:
        header = image.read(24)
    assert header[:8] == b'\x89PNG\r\n\x1a\n' and header[12:16] == b'IHDR', header
    return struct.unpack('>II', header[16:24])


@pytest.fixture(scope='module')
def sweep(tmp_path_factory):
    """Run the sweep once; (output folder, evaluate's output)."""
    folder = tmp_path_factory.mktemp('sweep')
    output = folder / 'sweep'
    command = ['nice', '-n', '5', 'rosrun', 'can_seeker', 'evaluate', '--world', 'empty',
               '--trials', str(TRIALS), '--seed', str(SEED), '--min-distance', '0.8',
               '--max-distance', '1.5', '--time-limit', '40', '--jobs', '2',
               '--sweep', 'can_stopper/stop_distance=%s' % ','.join(VALUES),
               '--sweep-output', str(output), '--log-dir', str(folder / 'logs')]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, timeout=TIMEOUT_S, check=False)
    sys.stdout.write(result.stdout[-4000:])
    assert result.returncode == 0, result.stdout[-4000:]
    return output, result.stdout


def test_sweep_writes_table_record_and_plot(sweep):
    output, _ = sweep
    assert sorted(os.listdir(str(output))) == ['sweep.json', 'sweep.md', 'sweep.png']
    assert png_size(str(output / 'sweep.png')) == PLOT_SIZE_PX
    assert os.path.getsize(str(output / 'sweep.png')) > 20000
    import matplotlib.image
    pixels = matplotlib.image.imread(str(output / 'sweep.png'))
    assert pixels.shape[:2] == PLOT_SIZE_PX[::-1] and pixels[..., :3].std() > 0.05


def test_both_settings_ran_the_same_seeds_and_stopped_at_their_own_distance(sweep):
    output, _ = sweep
    with open(str(output / 'sweep.json')) as stored:
        record = json.load(stored)
    settings = record['settings']
    assert [setting['setting'] for setting in settings] == [
        {'/can_stopper/stop_distance': value} for value in VALUES]
    mean_gaps = []
    for setting, value in zip(settings, VALUES):
        assert setting['settings']['seed'] == SEED
        assert setting['settings']['params'] == {'/can_stopper/stop_distance': value}
        trials = setting['trials']
        assert [trial['index'] for trial in trials] == list(range(TRIALS))
        successes = [trial for trial in trials if trial['success']]
        assert setting['summary']['successes'] == len(successes)
        assert len(successes) >= TRIALS - 1, [trial for trial in trials if not trial['success']]
        for trial in successes:
            assert abs(trial['gap_m'] - float(value)) <= GAP_TOLERANCE_M, trial
        mean_gaps.append(sum(trial['gap_m'] for trial in successes) / len(successes))
    # The same seeds give the same cans at both settings.
    cans = [[(trial['can_x_m'], trial['can_y_m']) for trial in setting['trials']]
            for setting in settings]
    assert cans[0] == cans[1]
    assert abs((mean_gaps[1] - mean_gaps[0]) - 0.2) <= GAP_TOLERANCE_M, mean_gaps


def test_table_lists_each_setting_with_its_success(sweep):
    output, printed = sweep
    with open(str(output / 'sweep.md')) as stored:
        table = stored.read()
    with open(str(output / 'sweep.json')) as stored:
        record = json.load(stored)
    assert table.startswith('%d trials per setting from seed %d, empty world' % (TRIALS, SEED))
    rows = [line for line in table.splitlines() if line.startswith('| 0.')]
    assert [row.split('|')[1].strip() for row in rows] == list(VALUES)
    for row, setting in zip(rows, record['settings']):
        cells = [cell.strip() for cell in row.strip('|').split('|')]
        summary = setting['summary']
        assert cells[1] == str(TRIALS)
        assert cells[2] == '%.0f%%' % (100.0 * summary['successes'] / summary['trials'])
    assert table.split('\n', 2)[2].strip() in printed
