"""What roslaunch would do with one of the package's launch files, asked without a master: the
parameters it would set (``--dump-params``) and the nodes it would start (``--nodes``)."""
import pathlib
import subprocess

import yaml

LAUNCH_DIR = pathlib.Path(__file__).resolve().parents[2] / 'launch'


def roslaunch_output(option: str, launch: str, *args: str) -> str:
    """roslaunch's output for ``option`` on launch/``launch`` with ``args``; fails the test
    with that output when roslaunch fails."""
    result = subprocess.run(['roslaunch', option, str(LAUNCH_DIR / launch)] + list(args),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, check=False)
    assert result.returncode == 0, result.stdout
    return result.stdout


def dumped_params(launch: str, *args: str) -> dict:
    """{parameter: value} that roslaunch would set."""
    return yaml.safe_load(roslaunch_output('--dump-params', launch, *args))


def launched_nodes(launch: str, *args: str) -> set:
    """The names of the nodes roslaunch would start."""
    return set(roslaunch_output('--nodes', launch, *args).split())
