"""Sweep settings: NODE/PARAM=VALUE overrides, the grid, the table and the plot."""
import argparse

import pytest

from can_seeker.evaluation.sweep import (override_arg, parse_override, parse_sweep, plot_sweep,
                                         setting_label, sweep_grid, sweep_table)


def test_overrides_name_a_node_parameter():
    assert parse_override('sim/camera_latency_s=0.1') == ('/sim/camera_latency_s', '0.1')
    assert parse_override('/can_stopper/max_linear = 0.2') == ('/can_stopper/max_linear', '0.2')
    for bad in ('camera_latency_s=0.1', 'sim/camera_latency_s', 'sim/=1', 'sim/x='):
        with pytest.raises(ValueError):
            parse_override(bad)
    with pytest.raises(argparse.ArgumentTypeError):
        override_arg('nonsense')


def test_a_grid_is_every_combination_first_sweep_slowest():
    sweeps = [parse_sweep('sim/a=1,2'), parse_sweep('can_stopper/b=x,y,z')]
    grid = sweep_grid(sweeps)
    assert len(grid) == 6
    assert grid[0] == {'/sim/a': '1', '/can_stopper/b': 'x'}
    assert grid[3] == {'/sim/a': '2', '/can_stopper/b': 'x'}
    assert setting_label(grid[5]) == 'a=2 b=z'
    with pytest.raises(ValueError):
        parse_sweep('sim/a=1,,2')


def summary(successes, gap_m, contacts, cpu_s=None):
    return {'trials': 10, 'success_rate': successes / 10.0, 'gap_error_mean_m': gap_m,
            'gap_error_max_m': gap_m, 'time_to_stop_median_s': 8.0, 'contacts': contacts,
            'setting_cpu_s': cpu_s,
            'setting_real_time_per_core': None if cpu_s is None else 120.0 / cpu_s}


def test_table_and_plot_show_every_setting(tmp_path):
    rows = [({'/sim/noise': '0'}, summary(10, 0.004, 0, cpu_s=150.0)),
            ({'/sim/noise': '8'}, summary(7, None, 2))]
    table = sweep_table(rows)
    lines = table.splitlines()
    assert lines[0].startswith('| `/sim/noise` | trials | success |')
    assert lines[2] == '| 0 | 10 | 100% | 4.0 | 4.0 | 8.0 | 0 | 150 | 0.80 |'
    assert lines[3] == '| 8 | 10 | 70% | n/a | n/a | 8.0 | 2 | n/a | n/a |'
    path = tmp_path / 'sweep.png'
    plot_sweep(rows, str(path), 'title')
    assert path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n' and path.stat().st_size > 5000
