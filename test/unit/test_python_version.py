"""Every Python file of the package runs on Python 3.8 (ROS Noetic on Ubuntu 20.04): vermin finds
the oldest interpreter each file needs from its syntax, modules and library calls."""
import pathlib
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parents[2]
PYTHON_DIRS = ('src', 'scripts', 'test', 'tools')
OLDEST_PYTHON = '3.8'


def vermin(*paths):
    """Run vermin against OLDEST_PYTHON; returns (exit code, report)."""
    command = [sys.executable, '-c', 'import sys; from vermin.main import main; sys.exit(main())',
               '-t=%s-' % OLDEST_PYTHON, '--violations', '--eval-annotations', '--no-tips',
               '--processes=1'] + [str(p) for p in paths]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, check=False)
    return result.returncode, result.stdout


def test_vermin_reports_code_that_needs_a_newer_python(tmp_path):
    newer = tmp_path / 'newer.py'
    newer.write_text('import zoneinfo\n\n\ndef names(text) -> list[str]:\n'
                     '    return "x-y".removeprefix("x")\n')
    code, report = vermin(newer)
    assert code != 0, report
    assert 'zoneinfo' in report and 'removeprefix' in report


def test_package_python_files_run_on_python_3_8():
    code, report = vermin(*(REPO / d for d in PYTHON_DIRS))
    assert code == 0, report
    assert 'Minimum required versions' in report
