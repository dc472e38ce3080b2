"""Result files (docs/results/*.json) and the pages written from them (docs/results.md, the
README's summary table).

A result file is one run of a tool: the ``command`` as a user types it, the ``commit`` of the
code it ran on, the ``date``, the ``machine`` (cores, CPU model, AVX-512), the ``kind`` of run
(the tool: evaluate, bench_loop, bench_node...) and the ``figures`` the tool printed. The
tools write one with ``--result FILE``; the tables list every file, one row each, named by it,
so a figure in the docs always traces back to a command and a commit.
"""
import datetime
import json
import os
import pathlib
import re
import shlex
import subprocess
from typing import Callable, Dict, List, Optional, Sequence, Tuple

from can_seeker.evaluation.batch import write_json_atomically

REQUIRED_FIELDS = ('command', 'commit', 'date', 'machine', 'kind', 'figures')
README_BEGIN = '<!-- results:begin -->'
README_END = '<!-- results:end -->'
SOURCE_DIR = pathlib.Path(__file__).resolve().parent


def code_commit(source_dir: pathlib.Path = SOURCE_DIR) -> Optional[str]:
    """The short hash of the commit checked out where the code runs from, with ``-dirty`` when
    tracked files other than the result files differ from it (a run that rewrites
    docs/results/ ran the same code); None outside a git checkout."""
    def git(*args):
        return subprocess.run(('git', '-C', str(source_dir)) + args, capture_output=True,
                              text=True, check=False)
    head = git('rev-parse', '--short', 'HEAD')
    if head.returncode != 0:
        return None
    dirty = git('diff', '--quiet', 'HEAD', '--', ':/', ':(exclude,top)docs/results').returncode != 0
    return head.stdout.strip() + ('-dirty' if dirty else '')


def machine(cpuinfo_path: str = '/proc/cpuinfo') -> dict:
    """The machine a run is made on: cores, CPU model and whether it has AVX-512 (None where
    /proc/cpuinfo does not say)."""
    try:
        with open(cpuinfo_path) as cpuinfo:
            text = cpuinfo.read()
    except OSError:
        text = ''
    model = re.search(r'^model name\s*:\s*(.+)$', text, re.MULTILINE)
    flags = re.search(r'^flags\s*:\s*(.+)$', text, re.MULTILINE)
    return {'cores': os.cpu_count(), 'cpu': model.group(1).strip() if model else None,
            'avx512': 'avx512f' in flags.group(1).split() if flags else None}


def command_line(tool: str, argv: Sequence[str]) -> str:
    """The command as a user types it: ``rosrun can_seeker TOOL ARGS``, quoted for a shell."""
    return ' '.join(['rosrun', 'can_seeker', tool] + [shlex.quote(arg) for arg in argv])


def result_record(kind: str, command: str, figures: dict, commit: Optional[str] = None,
                  date: Optional[str] = None, machine_info: Optional[dict] = None) -> dict:
    """A result file's record of a run made now on this machine (unless told otherwise)."""
    return {'command': command, 'commit': commit if commit is not None else code_commit(),
            'date': date or datetime.date.today().isoformat(),
            'machine': machine_info if machine_info is not None else machine(),
            'kind': kind, 'figures': figures}


def write_result(path: str, record: dict):
    """Write a result file (whole or not at all); ValueError naming what it lacks."""
    check_record(record)
    write_json_atomically(path, record)


def check_record(record: dict):
    """ValueError unless ``record`` has every field of a result file and names a command and a
    commit."""
    missing = [field for field in REQUIRED_FIELDS if field not in record]
    if missing:
        raise ValueError('missing %s' % ', '.join(missing))
    for field in ('command', 'commit', 'kind'):
        if not isinstance(record[field], str) or not record[field].strip():
            raise ValueError('no %s' % field)
    if not isinstance(record['figures'], dict):
        raise ValueError('figures is not an object')


def load_results(folder: pathlib.Path) -> List[Tuple[str, dict]]:
    """(file name, record) of every ``*.json`` in ``folder``, by name; ValueError naming the
    file that is not a result file."""
    results = []
    for path in sorted(folder.glob('*.json')):
        record = json.loads(path.read_text())
        try:
            check_record(record)
        except ValueError as error:
            raise ValueError('%s: %s' % (path, error))
        results.append((path.name, record))
    return results


def _number(value, scale=1.0, digits=1) -> str:
    return '' if value is None else '%.*f' % (digits, value * scale)


def _pair(figures, first, second, scale=1.0, digits=1, unit='') -> str:
    if figures.get(first) is None and figures.get(second) is None:
        return ''
    return '%s / %s%s' % (_number(figures.get(first), scale, digits),
                          _number(figures.get(second), scale, digits), unit)


def _evaluate_cells(figures: dict) -> List[str]:
    hidden = figures.get('can_hidden_at_start')
    found = figures.get('successes_can_hidden_at_start')
    timeouts = figures.get('lockstep_timeouts')
    return ['%s/%s' % (figures.get('successes', ''), figures.get('trials', '')),
            '' if figures.get('contacts') is None else str(figures['contacts']),
            _pair(figures, 'gap_error_mean_m', 'gap_error_max_m', 1000.0, 1, ' mm'),
            _pair(figures, 'bearing_error_mean_deg', 'bearing_error_max_deg', 1.0, 2, ' deg'),
            _pair(figures, 'time_to_stop_median_s', 'time_to_stop_max_s', 1.0, 1, ' s'),
            _number(figures.get('path_length_median_m'), digits=2),
            '' if hidden is None else '%d (%s)' % (hidden, '' if found is None else found),
            '' if timeouts is None else str(timeouts), check_text(figures)]


CHECKS = (('repeat_check', 'the same'), ('cpu_features_check', 'without wide SIMD kernels'),
          ('compared_with', 'against %(record)s'))
"""The comparisons evaluate can make of the same trials (a second run, or an earlier record),
and how a table names each (with the comparison's fields)."""


def check_text(figures: dict) -> str:
    """The repeat and CPU-features checks and the comparison with an earlier record a result
    holds, in words (empty: none)."""
    texts = []
    for key, label in CHECKS:
        check = figures.get(key)
        if check:
            texts.append('%s: %s, %s mm, %s deg' % (
                label % check, 'same outcomes' if not check.get('outcome_differs') else
                'outcomes differ in %s' % check['outcome_differs'],
                _number(check.get('max_position_diff_mm'), digits=4),
                _number(check.get('max_yaw_diff_deg'), digits=4)))
    return '; '.join(texts)


def _bench_loop_cells(figures: dict) -> List[str]:
    return ['%s/%s' % (figures.get('successes', ''), figures.get('trials', '')),
            _number(figures.get('cpu_ms_per_sim_s_total'), digits=0),
            _number(figures.get('real_time_per_core'), digits=2),
            ', '.join('%s %.0f' % item
                      for item in (figures.get('cpu_ms_per_sim_s') or {}).items())]


def _bench_node_cells(figures: dict) -> List[str]:
    return [', '.join('%s %.2f' % item
                      for item in (figures.get('ms_per_frame') or {}).items())]


KIND_TABLES: Dict[str, Tuple[Tuple[str, ...], Callable[[dict], List[str]]]] = {
    'evaluate': (('success', 'contacts', 'gap error mean / max', 'bearing mean / max',
                  'time to stop median / max (sim)', 'path median (m)',
                  'can out of view at start (found)', 'lockstep time-outs',
                  'run again (check: largest pose difference)'), _evaluate_cells),
    'bench_loop': (('success', 'CPU ms per sim s', 'x real time per core',
                    'CPU ms per sim s by process'), _bench_loop_cells),
    'bench_node': (('CPU ms per frame by node',), _bench_node_cells),
}
"""The columns of each kind's table after the file, command and commit, and its cells."""


def _kind_order(kind: str) -> Tuple[int, str]:
    """The kinds of :data:`KIND_TABLES` in its order, then any others by name."""
    known = list(KIND_TABLES)
    return (known.index(kind) if kind in known else len(known), kind)


def _generic_cells(figures: dict) -> List[str]:
    return [', '.join('%s %s' % (key, json.dumps(value)) for key, value in figures.items())]


def _cell(text) -> str:
    return str(text).replace('|', '\\|')


def _machine_text(info: dict) -> str:
    parts = []
    if info.get('cores') is not None:
        parts.append('%d cores' % info['cores'])
    if info.get('cpu'):
        parts.append(info['cpu'])
    if info.get('avx512') is not None:
        parts.append('AVX-512' if info['avx512'] else 'no AVX-512')
    return ', '.join(parts)


def results_markdown(results: Sequence[Tuple[str, dict]], link_prefix: str = 'results/') -> str:
    """docs/results.md: a section per kind, a row per result file (linked), in name order."""
    lines = ['# Results', '',
             'Generated by `rosrun can_seeker docs` from the files in `docs/results/`; do not '
             'edit by hand. Each row is one file: the command as typed, the commit of the code '
             'it ran on, the date and machine, and the figures the tool printed. A run writes '
             'its file with `--result FILE`; a file whose notes say "transcribed" holds '
             'figures copied from the README, not a run of its own.']
    kinds = sorted({record['kind'] for _, record in results}, key=_kind_order)
    for kind in kinds:
        columns, cells = KIND_TABLES.get(kind, (('figures',), _generic_cells))
        lines += ['', '## %s' % kind, '',
                  '| file | command | commit | date | machine | ' + ' | '.join(columns)
                  + ' | notes |', '|---' * (len(columns) + 6) + '|']
        for name, record in results:
            if record['kind'] != kind:
                continue
            row = ['[%s](%s%s)' % (name, link_prefix, name), '`%s`' % record['command'],
                   record['commit'], record['date'], _machine_text(record['machine'])]
            notes = '; '.join(record[key] for key in ('source', 'note') if record.get(key))
            lines.append('| ' + ' | '.join(_cell(cell) for cell in
                                           row + cells(record['figures']) + [notes]) + ' |')
    return '\n'.join(lines) + '\n'


def headline(record: dict) -> str:
    """A result's figures in one line, for the README's summary table."""
    figures = record['figures']
    if record['kind'] == 'evaluate':
        text = '%s/%s, %s contacts' % (figures.get('successes'), figures.get('trials'),
                                       figures.get('contacts'))
        times = _pair(figures, 'time_to_stop_median_s', 'time_to_stop_max_s', unit=' s')
        checks = check_text(figures)
        return (text + (', %s median / max time to stop' % times if times else '')
                + ('; run again %s' % checks if checks else ''))
    if record['kind'] == 'bench_loop':
        return '%sx real time per core (%s CPU ms per sim s)' % (
            _number(figures.get('real_time_per_core'), digits=2),
            _number(figures.get('cpu_ms_per_sim_s_total'), digits=0))
    if record['kind'] == 'bench_node':
        return 'CPU ms per frame: ' + _bench_node_cells(figures)[0]
    return _generic_cells(figures)[0]


def readme_table(results: Sequence[Tuple[str, dict]],
                 link_prefix: str = 'docs/results/') -> str:
    """The README's summary table: a row per result file, kinds in the order of
    :func:`results_markdown`; the commit and machine stay in the file it links and in
    docs/results.md (a manual names no commit)."""
    order = sorted(results, key=lambda item: (_kind_order(item[1]['kind']), item[0]))
    lines = ['| run | result | command |', '|---|---|---|']
    for name, record in order:
        lines.append('| ' + ' | '.join(_cell(cell) for cell in (
            '[%s](%s%s)' % (name[:-len('.json')], link_prefix, name), headline(record),
            '`%s`' % record['command'])) + ' |')
    return '\n'.join(lines)


def with_readme_table(readme: str, table: str) -> str:
    """``readme`` with ``table`` between its results markers, the rest unchanged; unchanged
    when it has no markers (ValueError when only one, or the end before the begin)."""
    begin, end = readme.find(README_BEGIN), readme.find(README_END)
    if begin < 0 and end < 0:
        return readme
    if begin < 0 or end < begin:
        raise ValueError('README.md: %s and %s out of order or one missing'
                         % (README_BEGIN, README_END))
    return '%s%s\n%s\n%s' % (readme[:begin], README_BEGIN, table, readme[end:])
