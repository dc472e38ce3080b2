"""Result files: what a record holds, the pages written from them, and that the committed pages
(docs/results.md, the README's table between its markers) are current and trace every row back
to a file in docs/results/ that names a command and a commit."""
import json
import pathlib
import re

import pytest

from can_seeker.evaluation.result_files import (README_BEGIN, README_END, check_record,
                                                command_line, load_results, machine,
                                                readme_table, result_record, results_markdown,
                                                with_readme_table, write_result)

ROOT = pathlib.Path(__file__).resolve().parents[2]
RESULTS = ROOT / 'docs' / 'results'
ROW_FILE = re.compile(r'^\| \[[^\]]+\]\((?:docs/)?results/([^)]+\.json)\) \|')

EVALUATE = result_record('evaluate', 'rosrun can_seeker evaluate --trials 2', {
    'trials': 2, 'successes': 1, 'contacts': 1, 'gap_error_mean_m': 0.0026,
    'gap_error_max_m': 0.0034, 'time_to_stop_median_s': 11.2, 'time_to_stop_max_s': 54.2},
    commit='abc1234', date='2026-01-02', machine_info={'cores': 2, 'cpu': 'X', 'avx512': False})


def test_a_record_names_its_command_commit_and_machine():
    check_record(EVALUATE)
    for field in ('command', 'commit'):
        with pytest.raises(ValueError, match=field):
            check_record(dict(EVALUATE, **{field: ''}))
    without_figures = {key: value for key, value in EVALUATE.items() if key != 'figures'}
    with pytest.raises(ValueError, match='figures'):
        check_record(without_figures)


def test_the_command_is_quoted_as_a_user_types_it():
    assert (command_line('evaluate', ['--scan-topics', '/camera_scan /scan', '--seed', '3'])
            == "rosrun can_seeker evaluate --scan-topics '/camera_scan /scan' --seed 3")


def test_the_machine_from_cpuinfo(tmp_path):
    cpuinfo = tmp_path / 'cpuinfo'
    cpuinfo.write_text('model name\t: Some CPU\nflags\t\t: fpu sse2 avx2 avx512f\n')
    info = machine(str(cpuinfo))
    assert (info['cpu'], info['avx512']) == ('Some CPU', True)
    assert machine(str(tmp_path / 'none'))['avx512'] is None


def test_written_results_load_back_and_refuse_what_is_not_one(tmp_path):
    write_result(str(tmp_path / 'run.json'), EVALUATE)
    assert load_results(tmp_path) == [('run.json', EVALUATE)]
    (tmp_path / 'bad.json').write_text(json.dumps(dict(EVALUATE, commit=None)))
    with pytest.raises(ValueError, match='bad.json'):
        load_results(tmp_path)


def test_a_row_per_file_with_its_figures():
    other = dict(EVALUATE, kind='bench_sim', figures={'real_time_factor': 3.5})
    page = results_markdown([('a.json', EVALUATE), ('b.json', other)])
    assert '## evaluate' in page and '## bench_sim' in page
    assert page.index('## evaluate') < page.index('## bench_sim')
    row = next(line for line in page.splitlines() if line.startswith('| [a.json]'))
    assert '| abc1234 | 2026-01-02 | 2 cores, X, no AVX-512 | 1/2 | 1 | 2.6 / 3.4 mm |' in row
    assert '| 11.2 / 54.2 s |' in row
    assert 'real_time_factor 3.5' in page
    table = readme_table([('a.json', EVALUATE)])
    assert '| [a](docs/results/a.json) | 1/2, 1 contacts, 11.2 / 54.2 s median / max' in table
    assert 'abc1234' not in table


def test_a_cpu_features_check_in_a_result_is_shown_beside_its_figures():
    checked = dict(EVALUATE, figures=dict(EVALUATE['figures'], cpu_features_check={
        'outcome_differs': [], 'max_position_diff_mm': 0.0072, 'max_yaw_diff_deg': 0.0001}))
    text = 'without wide SIMD kernels: same outcomes, 0.0072 mm, 0.0001 deg'
    assert text in readme_table([('a.json', checked)])
    assert text in results_markdown([('a.json', checked)])
    assert 'SIMD' not in readme_table([('a.json', EVALUATE)])


def test_a_comparison_with_an_earlier_record_is_shown_naming_it():
    compared = dict(EVALUATE, figures=dict(EVALUATE['figures'], compared_with={
        'outcome_differs': [3], 'max_position_diff_mm': 12.5, 'max_yaw_diff_deg': 0.25,
        'record': 'before.json'}))
    text = 'against before.json: outcomes differ in [3], 12.5000 mm, 0.2500 deg'
    assert text in results_markdown([('a.json', compared)])


def test_the_readme_table_goes_between_the_markers_only():
    readme = 'intro\n%s\nold table\n%s\nrest\n' % (README_BEGIN, README_END)
    assert with_readme_table(readme, 'T') == 'intro\n%s\nT\n%s\nrest\n' % (README_BEGIN,
                                                                          README_END)
    assert with_readme_table('no markers\n', 'T') == 'no markers\n'
    with pytest.raises(ValueError):
        with_readme_table('intro\n%s\n' % README_END, 'T')


def traced_rows(text):
    """The file each table row of ``text`` names, and how many table rows name none."""
    rows = [line for line in text.splitlines()
            if line.startswith('| ') and not line.startswith(('| file ', '| run '))]
    names = [ROW_FILE.match(row) for row in rows]
    return [match.group(1) for match in names if match], sum(match is None for match in names)


def test_the_committed_results_page_is_current_and_every_row_traces_to_a_file():
    results = load_results(RESULTS)
    assert results, 'docs/results/ holds no result file'
    page = (ROOT / 'docs' / 'results.md').read_text()
    assert page == results_markdown(results), \
        'docs/results.md is out of date: run rosrun can_seeker docs'
    names, untraced = traced_rows(page)
    assert untraced == 0
    assert sorted(names) == sorted(name for name, _ in results)
    for name in names:
        record = json.loads((RESULTS / name).read_text())
        assert record['command'].strip() and record['commit'].strip(), name


def test_the_readme_table_between_markers_is_current():
    readme = (ROOT / 'README.md').read_text()
    if README_BEGIN not in readme and README_END not in readme:
        pytest.skip('README.md has no results markers')
    results = load_results(RESULTS)
    assert readme == with_readme_table(readme, readme_table(results)), \
        'the README results table is out of date: run rosrun can_seeker docs'
    between = readme[readme.index(README_BEGIN):readme.index(README_END)]
    names, untraced = traced_rows(between)
    assert untraced == 0 and sorted(names) == sorted(name for name, _ in results)
