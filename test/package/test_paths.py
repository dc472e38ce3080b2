"""tools/paths.sh: where a checkout keeps its venv and workspace."""
import pathlib
import subprocess

REPO = pathlib.Path(__file__).resolve().parents[2]


def home_after_sourcing(environment):
    return subprocess.run(['bash', '-c', '. "$0/tools/paths.sh"; echo "$CAN_SEEKER_HOME"',
                           str(REPO)], env=dict(environment, PATH='/usr/bin:/bin'),
                          stdout=subprocess.PIPE, universal_newlines=True,
                          check=True).stdout.strip()


def test_an_explicit_home_is_kept():
    assert home_after_sourcing({'HOME': '/tmp', 'CAN_SEEKER_HOME': '/tmp/mine'}) == '/tmp/mine'


def test_the_home_of_another_checkouts_environment_is_not_taken():
    """A shell that sourced another checkout's tools/env.sh carries its CAN_SEEKER_*: setting
    this checkout up with them would re-point that checkout's workspace here."""
    default = home_after_sourcing({'HOME': '/tmp'})
    inherited = home_after_sourcing({'HOME': '/tmp', 'CAN_SEEKER_REPO': '/elsewhere/can_seeker',
                                     'CAN_SEEKER_HOME': '/tmp/elsewhere'})
    assert inherited == default != '/tmp/elsewhere'
    assert home_after_sourcing({'HOME': '/tmp', 'CAN_SEEKER_REPO': str(REPO.resolve()),
                                'CAN_SEEKER_HOME': '/tmp/mine'}) == '/tmp/mine'
