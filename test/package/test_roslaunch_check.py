"""roslaunch-check passes on every launch file and every rostest file: arguments resolve, included
files exist, every node's package and executable is found, every package used is a dependency
in package.xml (test files: test dependencies too, `-t`)."""
import os
import pathlib
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
import rospkg

REPO = pathlib.Path(__file__).resolve().parents[2]
LAUNCH_FILES = sorted(REPO.glob('launch/**/*.launch')) + sorted(REPO.glob('test/**/*.test'))
EXAMPLE_ARGS = {'bag': str(REPO / 'test' / 'data' / 'sim_can_320x240.bag')}
"""A value for each argument that a launch file requires (has no default)."""


def roslaunch_check_script():
    """roslaunch's own checker: <roslaunch share>/scripts/roslaunch-check (Debian's
    /usr/share/roslaunch, or /opt/ros/<distro>/share/roslaunch)."""
    return pathlib.Path(rospkg.RosPack().get_path('roslaunch')) / 'scripts' / 'roslaunch-check'


def required_args(launch_file):
    """Top-level <arg>s without a default or a value: roslaunch refuses the file without them."""
    root = ET.parse(str(launch_file)).getroot()
    return [arg.get('name') for arg in root.findall('arg')
            if arg.get('default') is None and arg.get('value') is None]


def roslaunch_check(launch_file, result_path, args=(), env=None):
    """Run roslaunch-check on one file; returns (exit code, output)."""
    command = ['nice', '-n', '10', sys.executable, str(roslaunch_check_script()),
               '-o', str(result_path)]
    if launch_file.suffix == '.test':
        command.append('-t')
    command += [str(launch_file)] + list(args)
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, check=False, env=env)
    return result.returncode, result.stdout


def test_there_are_launch_and_test_files():
    assert {'.launch', '.test'} <= {f.suffix for f in LAUNCH_FILES}


@pytest.mark.parametrize('launch_file', LAUNCH_FILES, ids=lambda f: str(f.relative_to(REPO)))
def test_roslaunch_check_passes(launch_file, tmp_path):
    missing = [name for name in required_args(launch_file) if name not in EXAMPLE_ARGS]
    assert missing == [], 'add an example value for these arguments to EXAMPLE_ARGS'
    args = ['%s:=%s' % (name, EXAMPLE_ARGS[name]) for name in required_args(launch_file)]
    code, output = roslaunch_check(launch_file, tmp_path / 'result.xml', args)
    assert code == 0, output
    assert 'passed' in output.splitlines()


def test_roslaunch_check_finds_a_missing_node_and_a_missing_argument(tmp_path):
    package = tmp_path / 'broken_launch'
    (package / 'launch').mkdir(parents=True)
    (package / 'package.xml').write_text(
        '<package format="2"><name>broken_launch</name><version>0.0.0</version>'
        '<description>d</description><maintainer email="m@example.com">m</maintainer>'
        '<license>BSD</license><buildtool_depend>catkin</buildtool_depend>'
        '<exec_depend>can_seeker</exec_depend></package>')
    broken = package / 'launch' / 'broken.launch'
    broken.write_text('<launch><arg name="bag"/>'
                      '<node pkg="can_seeker" type="no_such_node" name="x" args="$(arg bag)"/>'
                      '</launch>')
    paths = [str(tmp_path)] + rospkg.get_ros_package_path().split(':')
    env = dict(os.environ, ROS_PACKAGE_PATH=':'.join(paths))
    code, output = roslaunch_check(broken, tmp_path / 'result.xml', env=env)
    assert code != 0 and "requires the 'bag' arg" in output, output
    code, output = roslaunch_check(broken, tmp_path / 'result.xml', ['bag:=x.bag'], env=env)
    assert code != 0 and 'no_such_node' in output, output
