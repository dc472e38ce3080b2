"""The README's quick start runs as written: its first command (a launch, ending in ``&``) is
started in the background under a master of its own, then every other line is run in turn in a
shell and must exit 0 with the content it promises (a detection message, a known controller
state, the can moved, evaluate's trials passed)."""
import os
import pathlib
import re
import socket
import subprocess
import time

import pytest

from launch_process import stop_launch

REPO = pathlib.Path(__file__).resolve().parents[2]
STATES = ('SEARCH', 'EXPLORE', 'APPROACH', 'STOPPED', 'LOST', 'WANDER')
COMMAND_TIMEOUT_S = 120
EVALUATE_TIMEOUT_S = 600


def quick_start_commands():
    """The commands of the first ``bash`` block under '## Quick start', comments stripped."""
    readme = (REPO / 'README.md').read_text()
    section = readme.split('\n## Quick start', 1)[1].split('\n## ', 1)[0]
    block = re.search(r'```bash\n(.*?)```', section, re.S).group(1)
    commands = []
    for line in block.splitlines():
        command = re.sub(r'\s+#.*$', '', line).strip()
        if command:
            commands.append(command)
    return commands


def free_port():
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def test_the_quick_start_begins_with_a_launch_in_the_background():
    commands = quick_start_commands()
    assert commands[0].startswith('roslaunch can_seeker ') and commands[0].endswith('&')
    assert len(commands) >= 4


def expect(command, output):
    """The content each kind of quick-start line promises, as an assertion on its output."""
    if 'rostopic echo' in command and 'detection' in command:
        assert re.search(r'^found: (True|False)$', output, re.M), output
        assert re.search(r'^confidence: ', output, re.M), output
    elif 'rostopic echo' in command and 'state' in command:
        assert re.search(r'^data: "(%s)' % '|'.join(STATES), output, re.M), output
    elif 'place_can' in command:
        assert re.search(r'^success: True$', output, re.M), output
    elif 'evaluate' in command:
        assert re.search(r'^\| success rate \| (\d+)/\1 ', output, re.M), output[-2000:]


def wait_for_topic(topic, environment, launch, timeout_s=COMMAND_TIMEOUT_S):
    """Wait until the launch's master lists ``topic`` (the nodes are up)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        assert launch.poll() is None, 'the launch ended before its nodes came up'
        listing = subprocess.run(['rostopic', 'list'], stdout=subprocess.PIPE,
                                 stderr=subprocess.DEVNULL, universal_newlines=True,
                                 env=environment, check=False)
        if topic in listing.stdout.split():
            return
        time.sleep(1.0)
    pytest.fail('%s did not appear within %d s' % (topic, timeout_s))


def test_every_quick_start_command_runs_as_written(tmp_path):
    commands = quick_start_commands()
    environment = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % free_port(),
                       ROS_HOME=str(tmp_path / 'ros_home'))
    launch_log = open(str(tmp_path / 'roslaunch.log'), 'w')
    launch = subprocess.Popen(['bash', '-c', 'exec ' + commands[0].rstrip('&').strip()],
                              stdout=launch_log, stderr=subprocess.STDOUT,
                              start_new_session=True, env=environment, cwd=str(tmp_path))
    try:
        wait_for_topic('/can_stopper/state', environment, launch)
        for command in commands[1:]:
            timeout_s = EVALUATE_TIMEOUT_S if 'evaluate' in command else COMMAND_TIMEOUT_S
            result = subprocess.run(['bash', '-c', command], stdout=subprocess.PIPE,
                                    stderr=subprocess.STDOUT, universal_newlines=True,
                                    timeout=timeout_s, env=environment, cwd=str(tmp_path),
                                    check=False)
            assert result.returncode == 0, '%s\n%s' % (command, result.stdout[-3000:])
            expect(command, result.stdout)
            assert launch.poll() is None, 'the launch ended during: ' + command
    finally:
        stop_launch(launch)
        launch_log.close()

