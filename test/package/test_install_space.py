"""The install space works on its own, as binary packages and `catkin_make install` users get it.

A copy of this package is built with `catkin_make install` in a temporary workspace (in an
environment holding only the system's ROS), then its source, build and devel spaces are deleted.
With only install/setup.bash sourced: every file of the package's source (the files git tracks)
is installed, every module, script and launch
file resolves into the install space, `roslaunch can_seeker demo.launch` finds the can and stops
in front of it, and `rosrun can_seeker evaluate --trials 2` passes.
"""
import json
import os
import pathlib
import shutil
import socket
import subprocess
import sys
import tempfile
import time

import pytest
import yaml

from launch_process import stop_launch

REPO = pathlib.Path(__file__).resolve().parents[2]
PACKAGE = 'can_seeker'
NOT_INSTALLED_DIRS = {'src', 'scripts', 'test', 'tools', 'msg', 'srv', 'debian', 'doc', 'docs'}
"""Top-level folders that are not installed as they are under share/ (code, tests, tooling;
messages and services are installed by message generation)."""
COPY_IGNORE = shutil.ignore_patterns('.git', '__pycache__', '*.pyc', '.pytest_cache',
                                     'demo_output', 'bench_output')
SYSTEM_PATH = '/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin'
NICE = ['nice', '-n', '10']
"""The build yields the CPU to the timing-sensitive rostests that run beside this test (the nodes
do not: evaluate gives them 60 s to come up)."""
BUILD_TIMEOUT_S = 600
DEMO_TIMEOUT_S = 300
EVALUATE_TIMEOUT_S = 600


def ros_underlay():
    """The ROS installation this run builds against: the first catkin prefix on
    CMAKE_PREFIX_PATH that has a setup.bash and is not a workspace of this package (e.g.
    /opt/ros/noetic); None where ROS comes from the system itself (Debian's /usr)."""
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(os.pathsep):
        path = pathlib.Path(prefix) if prefix else None
        if path and (path / 'setup.bash').is_file() and not (path / 'share' / PACKAGE).exists():
            return path
    return None


def free_port():
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


class InstallSpace:
    """A built install space and a clean environment (no devel space, no source tree)."""

    def __init__(self, root):
        self.root = root
        self.workspace = root / 'ws'
        self.prefix = self.workspace / 'install'
        self.share = self.prefix / 'share' / PACKAGE
        self.ros_home = root / 'ros_home'
        self.ros_home.mkdir()

    def environment(self, **extra):
        """Only what a user's login shell has, plus the test interpreter's bin directory first
        (the venv, so nodes run the interpreter that has pybullet)."""
        environment = {'HOME': os.environ['HOME'], 'LANG': 'C.UTF-8',
                       'PATH': os.path.dirname(sys.executable) + os.pathsep + SYSTEM_PATH,
                       'ROS_HOME': str(self.ros_home), 'ROS_HOSTNAME': '127.0.0.1',
                       'ROS_MASTER_URI': 'http://127.0.0.1:%d' % free_port(),
                       'PYTHONDONTWRITEBYTECODE': '1'}
        environment.update(extra)
        return environment

    def build(self, log_path):
        """catkin_make install of a copy of the repository, then delete everything but install/."""
        shutil.copytree(str(REPO), str(self.workspace / 'src' / PACKAGE), ignore=COPY_IGNORE)
        underlay = ros_underlay()
        script = ('set -e; [ -z "$UNDERLAY" ] || { set +u; . "$UNDERLAY/setup.bash"; }; '
                  'cd "$WORKSPACE" && catkin_make install -DPYTHON_EXECUTABLE="$PYTHON" '
                  '-DCATKIN_ENABLE_TESTING=OFF -DCMAKE_BUILD_TYPE=Release')
        environment = self.environment(UNDERLAY=str(underlay or ''), WORKSPACE=str(self.workspace),
                                       PYTHON=sys.executable)
        with open(str(log_path), 'w') as log:
            result = subprocess.run(NICE + ['bash', '-c', script], stdout=log,
                                    stderr=subprocess.STDOUT,
                                    env=environment, timeout=BUILD_TIMEOUT_S, check=False)
        assert result.returncode == 0, log_path.read_text()[-3000:]
        for space in ('src', 'build', 'devel'):
            shutil.rmtree(str(self.workspace / space))

    def command(self, args):
        """``args`` run with only install/setup.bash sourced (catkin's setup reads the positional
        arguments, so they are cleared first)."""
        script = 'command=("$@"); set --; set +u; . "$INSTALL/setup.bash"; exec "${command[@]}"'
        return ['bash', '-c', script, 'install-env'] + [str(a) for a in args]

    def run(self, args, timeout_s, **extra):
        return subprocess.run(self.command(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              universal_newlines=True, timeout=timeout_s, check=False,
                              env=self.environment(INSTALL=str(self.prefix), **extra))


@pytest.fixture(scope='module')
def install_space():
    root = pathlib.Path(tempfile.mkdtemp(prefix='can_seeker_install_'))
    try:
        space = InstallSpace(root)
        start = time.monotonic()
        space.build(root / 'build.log')
        print('install space built in %.1f s' % (time.monotonic() - start))
        yield space
    finally:
        shutil.rmtree(str(root), ignore_errors=True)


def source_files():
    """The package's source files, relative to REPO: those git tracks (and the work tree still
    has), or every file under REPO's folders but dot-folders when it is not a git checkout;
    what else lies there (outputs, caches) is not the package."""
    try:
        listed = subprocess.run(['git', '-C', str(REPO), 'ls-files', '-z'], check=True,
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL).stdout
    except (OSError, subprocess.CalledProcessError):
        listed = b''
    tracked = [pathlib.PurePath(name) for name in listed.decode().split('\0')
               if name and (REPO / name).is_file()]
    if tracked:
        return tracked
    return [path.relative_to(REPO) for path in REPO.rglob('*') if path.is_file()
            and not any(part.startswith('.') for part in path.relative_to(REPO).parts)]


def source_files_in(folder, suffix=''):
    """The source files under the top-level ``folder`` that end with ``suffix``."""
    return [path for path in source_files()
            if path.parts[0] == folder and len(path.parts) > 1 and path.name.endswith(suffix)]


def package_scripts():
    return sorted(path.name for path in source_files_in('scripts') if len(path.parts) == 2)


def is_inside(path, folder):
    return os.path.realpath(str(path)).startswith(os.path.realpath(str(folder)) + os.sep)


def test_every_file_is_installed(install_space):
    python_roots = list(install_space.prefix.glob('lib/python3*/*-packages'))
    assert len(python_roots) == 1, python_roots
    python_package = python_roots[0] / PACKAGE
    files = source_files()
    wanted = [install_space.share / 'package.xml']
    wanted += [install_space.share / f for f in files
               if len(f.parts) > 1 and not f.parts[0].startswith('.')
               and f.parts[0] not in NOT_INSTALLED_DIRS]
    messages = source_files_in('msg', '.msg')
    services = source_files_in('srv', '.srv')
    wanted += [install_space.share / 'msg' / f.name for f in messages]
    wanted += [install_space.share / 'srv' / f.name for f in services]
    wanted += [python_package / f.relative_to('src', PACKAGE) for f in source_files_in('src', '.py')
               if f.parts[:2] == ('src', PACKAGE)]
    wanted += [python_package / 'msg' / ('_%s.py' % f.stem) for f in messages]
    wanted += [python_package / 'srv' / ('_%s.py' % f.stem) for f in services]
    wanted += [python_package / 'cfg' / ('%sConfig.py' % f.stem)
               for f in source_files_in('cfg', '.cfg')]
    assert any(p.suffix == '.launch' for p in wanted)
    assert [str(p) for p in wanted if not p.is_file()] == []
    scripts = package_scripts()
    installed = install_space.prefix / 'lib' / PACKAGE
    assert [s for s in scripts if not os.access(str(installed / s), os.X_OK)] == []


IMPORT_EVERYTHING = '''
import json, pkgutil, sys, importlib
import can_seeker, can_seeker.msg, can_seeker.srv, can_seeker.cfg
names = [m.name for m in pkgutil.walk_packages(can_seeker.__path__, 'can_seeker.')]
files = {name: importlib.import_module(name).__file__ for name in ['can_seeker'] + names}
json.dump({'files': files, 'sys_path': sys.path}, open(sys.argv[1], 'w'))
'''


def test_modules_scripts_and_launch_files_come_from_the_install_space(install_space, tmp_path):
    result = install_space.run(['env'], 60)
    environment = dict(line.split('=', 1) for line in result.stdout.splitlines() if '=' in line)
    search_paths = {'CMAKE_PREFIX_PATH': 'share/' + PACKAGE, 'PYTHONPATH': PACKAGE,
                    'ROS_PACKAGE_PATH': PACKAGE}
    for variable, provides_package in search_paths.items():
        entries = [e for e in environment.get(variable, '').split(os.pathsep) if e]
        assert any(is_inside(e, install_space.prefix) or e == str(install_space.prefix)
                   for e in entries), (variable, entries)
        others = [e for e in entries
                  if not (is_inside(e, install_space.prefix) or e == str(install_space.prefix))]
        assert [e for e in others
                if is_inside(e, REPO) or (pathlib.Path(e) / provides_package).exists()] == [], \
            (variable, entries)
    report = tmp_path / 'modules.json'
    result = install_space.run(['python3', '-c', IMPORT_EVERYTHING, report], 120)
    assert result.returncode == 0, result.stdout
    files = json.loads(report.read_text())['files']
    assert {'can_seeker.msg._CanDetection', 'can_seeker.nodes.sim_node'} <= set(files)
    assert {name: path for name, path in files.items()
            if not is_inside(path, install_space.prefix)} == {}
    result = install_space.run(['rospack', 'find', PACKAGE], 60)
    assert result.stdout.strip() == str(install_space.share)
    for script in package_scripts():
        result = install_space.run(['rosrun', '--prefix', 'echo', PACKAGE, script], 60)
        assert result.stdout.strip() == str(install_space.prefix / 'lib' / PACKAGE / script)


def test_robot_launch_checks_its_profile_with_the_installed_tool(install_space):
    """robot.launch runs robot_params --check while loading: from the install space too."""
    result = install_space.run(['roslaunch', '--dump-params', PACKAGE, 'robot.launch',
                                'robot:=turtlebot3_burger'], 120)
    assert result.returncode == 0, result.stdout
    assert yaml.safe_load(result.stdout)['/robot_profile_name'] == 'turtlebot3_burger', \
        result.stdout


def test_demo_launch_finds_the_can_and_stops_in_front_of_it(install_space, tmp_path):
    port = free_port()
    master = 'http://127.0.0.1:%d' % port
    launch_log = open(str(tmp_path / 'roslaunch.log'), 'w')
    launch = subprocess.Popen(
        install_space.command(['roslaunch', '-p', port, PACKAGE, 'demo.launch',
                               'can_placement:=fixed', 'can_x:=1.2', 'can_y:=0.4',
                               'real_time_factor:=0']),
        stdout=launch_log, stderr=subprocess.STDOUT, start_new_session=True,
        env=install_space.environment(INSTALL=str(install_space.prefix), ROS_MASTER_URI=master))
    report_path = tmp_path / 'demo.json'
    try:
        probe = install_space.run(['python3', REPO / 'test' / 'package' / 'demo_probe.py',
                                   report_path, DEMO_TIMEOUT_S], DEMO_TIMEOUT_S + 60,
                                  ROS_MASTER_URI=master)
        assert probe.returncode == 0, probe.stdout
    finally:
        stop_launch(launch)
        launch_log.close()
    report = json.loads(report_path.read_text())
    assert report['detections_found'] > 0, report
    assert 0.5 < report['first_ranged']['range_m'] < 1.5, report
    assert 'APPROACH' in report['states'] and report['states'][-1] == 'STOPPED', report
    assert abs(report['gap_m'] - report['stop_distance_m']) <= 0.02, report
    installed_scripts = install_space.prefix / 'lib' / PACKAGE
    for node, script in (('/sim', 'sim_node'), ('/image_converter', 'image_converter'),
                         ('/can_stopper', 'can_stopper')):
        assert str(installed_scripts / script) in report['nodes'][node], report['nodes'][node]
    assert all(is_inside(path, install_space.prefix) for path in report['modules'].values())


def test_evaluate_runs_two_successful_trials(install_space, tmp_path):
    results = tmp_path / 'evaluate.json'
    result = install_space.run(['rosrun', PACKAGE, 'evaluate', '--trials', '2', '--json', results,
                                '--log-dir', tmp_path / 'evaluate_logs'], EVALUATE_TIMEOUT_S)
    assert result.returncode == 0, result.stdout[-3000:]
    summary = json.loads(results.read_text())['summary']
    assert summary['trials'] == 2 and summary['successes'] == 2, summary
