"""Parameter settings for evaluations: ``NODE/PARAM=VALUE`` overrides, sweep grids over them,
and the degradation table and plot of a sweep (success, true gap error, time to stop and
contacts against each setting).
"""
import argparse
import difflib
import itertools
from typing import Dict, List, Sequence, Tuple

from can_seeker.control.controller import PARAMS as CAN_STOPPER_PARAMS
from can_seeker.params import unknown_param_message
from can_seeker.sim.simulation import PARAMS as SIM_PARAMS
from can_seeker.vision.camera_scan import PARAMS as OBSTACLE_SCAN_PARAMS
from can_seeker.vision.report import PARAMS as IMAGE_CONVERTER_PARAMS

Setting = Dict[str, str]
"""Parameter name (``/node/param``) -> value as roslaunch reads it."""
EVALUATED_NODES = {'can_stopper': CAN_STOPPER_PARAMS, 'image_converter': IMAGE_CONVERTER_PARAMS,
                   'obstacle_scan': OBSTACLE_SCAN_PARAMS, 'sim': SIM_PARAMS}
"""The nodes demo.launch starts for evaluate and demo, by node name, with the parameters each
reads: an override must name a parameter one of them declares, as one set and never read
would be silently ignored for a whole evaluation."""


def parse_override(text: str) -> Tuple[str, str]:
    """``NODE/PARAM=VALUE`` -> ('/NODE/PARAM', 'VALUE'); ValueError if it is not of that form,
    or names a node not in EVALUATED_NODES or a parameter that node does not declare."""
    name, separator, value = text.partition('=')
    name = name.strip().strip('/')
    if not separator or '/' not in name or not value.strip() or not all(name.split('/')):
        raise ValueError('expected NODE/PARAM=VALUE (e.g. sim/realism/camera_read_noise=4), '
                         'got %r' % (text,))
    node, _, param = name.partition('/')
    if node not in EVALUATED_NODES:
        likely = difflib.get_close_matches(node, EVALUATED_NODES, n=1, cutoff=0.6)
        raise ValueError('%s/%s: %s is not a node of the closed loop%s; its nodes are %s' % (
            node, param, node, ' (did you mean %s?)' % likely[0] if likely else '',
            ', '.join(sorted(EVALUATED_NODES))))
    problem = unknown_param_message(param, EVALUATED_NODES[node], node + '/')
    if problem:
        raise ValueError(problem)
    return '/' + name, value.strip()


def override_arg(text: str) -> Tuple[str, str]:
    """:func:`parse_override` for argparse: a bad value is an ArgumentTypeError."""
    try:
        return parse_override(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error))


def parse_sweep(text: str) -> Tuple[str, List[str]]:
    """``NODE/PARAM=v1,v2,...`` -> ('/NODE/PARAM', [v1, v2, ...]); ValueError otherwise."""
    name, values = parse_override(text)
    choices = [value.strip() for value in values.split(',')]
    if not all(choices):
        raise ValueError('a sweep lists values separated by commas, got %r' % (text,))
    return name, choices


def sweep_grid(sweeps: Sequence[Tuple[str, Sequence[str]]]) -> List[Setting]:
    """Every combination of the swept values, the first sweep varying slowest."""
    names = [name for name, _ in sweeps]
    return [dict(zip(names, values))
            for values in itertools.product(*(values for _, values in sweeps))]


def setting_label(setting: Setting) -> str:
    """A short text naming a setting: ``param=value`` joined by spaces."""
    return ' '.join('%s=%s' % (name.rsplit('/', 1)[-1], value)
                    for name, value in setting.items())


ROW_FIELDS = (('success', 'success_rate', 100.0, '%.0f%%'),
              ('mean gap error (mm)', 'gap_error_mean_m', 1000.0, '%.1f'),
              ('max gap error (mm)', 'gap_error_max_m', 1000.0, '%.1f'),
              ('median time to stop (s)', 'time_to_stop_median_s', 1.0, '%.1f'),
              ('trials with contact', 'contacts', 1.0, '%d'),
              ('CPU s', 'setting_cpu_s', 1.0, '%.0f'),
              ('x real time per core', 'setting_real_time_per_core', 1.0, '%.2f'))


def sweep_table(rows: Sequence[Tuple[Setting, dict]]) -> str:
    """Markdown table of (setting, evaluate summary) rows."""
    names = list(rows[0][0]) if rows else []
    header = ['`%s`' % name for name in names] + ['trials'] + [title for title, *_ in ROW_FIELDS]
    lines = ['| ' + ' | '.join(header) + ' |', '|' + '---|' * len(header)]
    for setting, summary in rows:
        cells = [setting[name] for name in names] + [str(summary['trials'])]
        for _, key, scale, form in ROW_FIELDS:
            value = summary.get(key)
            cells.append('n/a' if value is None else form % (value * scale))
        lines.append('| ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines)


def plot_sweep(rows: Sequence[Tuple[Setting, dict]], path: str, title: str = ''):
    """PNG of success, mean true gap error, median time to stop and trials with contact
    against the settings (one point per setting, in order)."""
    import matplotlib
    matplotlib.use('Agg')
    from matplotlib import pyplot

    labels = [setting_label(setting) for setting, _ in rows]
    positions = list(range(len(rows)))
    figure, axes = pyplot.subplots(1, 4, figsize=(14, 3.6))
    for axis, (heading, key, scale, _) in zip(axes, (ROW_FIELDS[0], ROW_FIELDS[1],
                                                     ROW_FIELDS[3], ROW_FIELDS[4])):
        values = [summary.get(key) for _, summary in rows]
        axis.plot([p for p, v in zip(positions, values) if v is not None],
                  [v * scale for v in values if v is not None], 'o-')
        axis.set_title(heading, fontsize=10)
        axis.set_xticks(positions)
        axis.set_xticklabels(labels, rotation=30, ha='right', fontsize=8)
        axis.grid(True, alpha=0.3)
        if key == 'success_rate':
            axis.set_ylim(-5, 105)
        elif key == 'contacts':
            axis.set_ylim(-0.5, max([1.0] + [v for v in values if v is not None]) + 0.5)
        else:
            axis.set_ylim(bottom=0)
    if title:
        figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    pyplot.close(figure)
