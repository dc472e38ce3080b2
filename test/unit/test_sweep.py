"""Sweep settings: NODE/PARAM=VALUE overrides, the grid, the table and the plot."""
import argparse

import pytest

from can_seeker.evaluation.sweep import (EVALUATED_NODES, override_arg, parse_override,
                                         parse_sweep, plot_sweep, setting_label, sweep_grid,
                                         sweep_table)


def test_overrides_name_a_node_parameter():
    assert parse_override('sim/realism/camera_latency_s=0.1') == (
        '/sim/realism/camera_latency_s', '0.1')
    assert parse_override('/can_stopper/max_linear = 0.2') == ('/can_stopper/max_linear', '0.2')
    for bad in ('camera_latency_s=0.1', 'sim/realism/camera_latency_s', 'sim/=1', 'sim/x='):
        with pytest.raises(ValueError):
            parse_override(bad)
    with pytest.raises(argparse.ArgumentTypeError):
        override_arg('nonsense')


def test_a_simulator_parameter_it_does_not_declare_is_refused_naming_the_one_meant():
    """A knob of the old flat spelling would be set and never read: refused up front."""
    with pytest.raises(argparse.ArgumentTypeError,
                       match=r'sim/camera_latency_s is not a parameter; did you mean '
                             r'sim/realism/camera_latency_s\?'):
        override_arg('sim/camera_latency_s=0.1')
    with pytest.raises(ValueError, match='sim/realism is a namespace, not a parameter: it '
                                         'holds sim/realism/preset, '):
        parse_override('sim/realism=harsh')
    with pytest.raises(ValueError, match='did you mean sim/cmd_timeout'):
        parse_sweep('sim/cmd_timeuot=0.5,1')
    assert parse_override('sim/realism/preset=harsh') == ('/sim/realism/preset', 'harsh')


@pytest.mark.parametrize('typo,meant', [
    ('can_stopper/stop_distnce', 'can_stopper/stop_distance'),
    ('image_converter/hue_mx', 'image_converter/hue_max'),
    ('obstacle_scan/max_rnge', 'obstacle_scan/max_range'),
    ('sim/realism/camera_latncy_s', 'sim/realism/camera_latency_s'),
])
def test_a_typo_in_any_evaluated_node_is_refused_naming_the_parameter_meant(typo, meant):
    with pytest.raises(ValueError, match=r'^%s is not a parameter; did you mean %s\?$'
                                         % (typo, meant)):
        parse_override(typo + '=1')


def test_a_node_the_closed_loop_does_not_start_is_refused_naming_those_it_does():
    with pytest.raises(ValueError, match=r'can_stoper is not a node of the closed loop \(did you '
                                         r'mean can_stopper\?\); its nodes are can_stopper, '
                                         r'image_converter, obstacle_scan, sim$'):
        parse_override('can_stoper/max_linear=0.2')
    with pytest.raises(ValueError, match=r'twist_mux is not a node of the closed loop; its '
                                         r'nodes are can_stopper, '):
        parse_override('twist_mux/inputs=cmd_vel:1:0.5')


@pytest.mark.parametrize('node', sorted(EVALUATED_NODES))
def test_every_declared_parameter_of_an_evaluated_node_is_accepted(node):
    params = EVALUATED_NODES[node]
    assert params
    for spec in params:
        assert parse_override('%s/%s=1' % (node, spec.name)) == ('/%s/%s' % (node, spec.name),
                                                                  '1')


def test_a_grid_is_every_combination_first_sweep_slowest():
    sweeps = [parse_sweep('sim/seed=1,2'), parse_sweep('can_stopper/stop_distance=0.2,0.25,0.3')]
    grid = sweep_grid(sweeps)
    assert len(grid) == 6
    assert grid[0] == {'/sim/seed': '1', '/can_stopper/stop_distance': '0.2'}
    assert grid[3] == {'/sim/seed': '2', '/can_stopper/stop_distance': '0.2'}
    assert setting_label(grid[5]) == 'seed=2 stop_distance=0.3'
    with pytest.raises(ValueError):
        parse_sweep('sim/seed=1,,2')


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
