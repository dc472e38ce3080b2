"""`make setup` (tools/setup.sh) on a machine with an installed ROS 1 under /opt/ros uses it: it
sources the distribution's setup.bash, leaves the Debian package list alone, asks rosdep for the
missing dependencies (installing them with rosdep when some are) and builds the workspace on top
of that ROS.

The ROS installation here is a stand-in under a temporary CAN_SEEKER_ROS_ROOT: a catkin prefix
(.catkin marker) whose setup.bash puts it on CMAKE_PREFIX_PATH over this machine's ROS, with a
recording `rosdep` (the real one needs its database from the network). Everything else is real:
setup.sh, the existing venv, catkin_make, the devel space it writes.
"""
import os
import pathlib
import stat
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SYSTEM_PATH = '/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin'
SETUP_TIMEOUT_S = 600


def write_executable(path, text):
    path.write_text(text)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)


def fake_ros(root, record):
    """A ROS 1 distribution stand-in (/opt/ros/one: setup.bash, .catkin marker, a rosdep that
    records its calls and reports missing dependencies while root/missing exists) and, found
    first, a ROS 2 style /opt/ros/humble (no .catkin) that setup must pass over: sourcing it
    fails."""
    prefix = root / 'one'
    (prefix / 'bin').mkdir(parents=True)
    (prefix / '.catkin').write_text('')
    (prefix / 'setup.bash').write_text(
        'export CMAKE_PREFIX_PATH="%s${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"\n'
        'export PATH="%s:$PATH"\n' % (prefix, prefix / 'bin'))
    write_executable(prefix / 'bin' / 'rosdep',
                     '#!/bin/sh\necho "$*" >> "%s"\n'
                     'if [ "$1" = check ] && [ -f "%s" ]; then\n'
                     '  echo "System dependencies have not been satisfied:"; exit 1\n'
                     'fi\necho "All system dependencies have been satisfied"\n'
                     % (record, root / 'missing'))
    (root / 'humble').mkdir()
    (root / 'humble' / 'setup.bash').write_text('echo "sourced a ROS 2 setup" >&2; exit 1\n')
    return prefix


def run_setup(environment, home):
    result = subprocess.run(['nice', '-n', '10', 'bash', str(REPO / 'tools' / 'setup.sh')],
                            env=environment,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, timeout=SETUP_TIMEOUT_S, check=False)
    log = (home / 'setup.log').read_text() if (home / 'setup.log').exists() else ''
    assert result.returncode == 0, result.stdout + log[-3000:]
    return result


@pytest.mark.skipif(sys.prefix == sys.base_prefix,
                    reason='runs setup.sh with the venv of make setup, and this is no venv')
def test_setup_builds_on_an_installed_ros_without_apt(tmp_path):
    rosdep_calls = tmp_path / 'rosdep_calls.txt'
    apt_calls = tmp_path / 'apt_calls.txt'
    prefix = fake_ros(tmp_path / 'opt_ros', rosdep_calls)
    fake_bin = tmp_path / 'bin'
    fake_bin.mkdir()
    for tool in ('apt-get', 'sudo'):
        write_executable(fake_bin / tool, '#!/bin/sh\necho "%s $*" >> "%s"\nexit 1\n'
                         % (tool, apt_calls))
    home = tmp_path / 'home'
    environment = {'HOME': os.environ['HOME'], 'LANG': 'C.UTF-8',
                   'PATH': '%s:%s' % (fake_bin, SYSTEM_PATH),
                   'CAN_SEEKER_ROS_ROOT': str(tmp_path / 'opt_ros'),
                   'CAN_SEEKER_HOME': str(home),
                   'CAN_SEEKER_VENV': os.path.dirname(os.path.dirname(sys.executable))}
    result = run_setup(environment, home)
    assert 'using the installed ROS at %s' % prefix in result.stdout
    assert 'Debian packages' not in result.stdout
    assert not apt_calls.exists(), apt_calls.read_text()
    assert rosdep_calls.read_text().splitlines() == [
        'check --from-paths %s --ignore-src --skip-keys=python3-pybullet-pip' % REPO]
    chained = subprocess.run(
        ['bash', '-c', 'set +u; . "$1/devel/setup.bash"; echo "$CMAKE_PREFIX_PATH"', 'devel',
         str(home / 'ws')], env={'HOME': os.environ['HOME'], 'PATH': SYSTEM_PATH},
        stdout=subprocess.PIPE, universal_newlines=True, check=True)
    assert chained.stdout.strip().split(':') == [str(home / 'ws' / 'devel'), str(prefix)]

    (tmp_path / 'opt_ros' / 'missing').write_text('')
    result = run_setup(environment, home)
    assert 'rosdep: missing dependencies' in result.stdout
    assert 'catkin workspace: up to date' in result.stdout
    rosdep_options = '--from-paths %s --ignore-src --skip-keys=python3-pybullet-pip' % REPO
    as_root = ' --as-root apt:false' if os.getuid() == 0 else ''
    assert rosdep_calls.read_text().splitlines()[1:] == [
        'check ' + rosdep_options, 'install %s%s -y' % (rosdep_options, as_root)]
    assert not apt_calls.exists(), apt_calls.read_text()
