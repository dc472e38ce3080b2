"""Every argument of robot.launch, the launch a robot owner starts from, is named where the
README's "On your robot" and nodes.md's robot.launch section list its arguments, and every
argument of playback.launch (a robot's bag played back) in tools.md's playback paragraph."""
import pathlib
import re
import xml.etree.ElementTree as ET

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DERIVED = {'profile_file'}  # computed from robot, documented as "set robot instead"


def launch_args(name='robot.launch'):
    root = ET.parse(str(REPO / 'launch' / name)).getroot()
    return [arg.get('name') for arg in root.findall('arg') if arg.get('name') not in DERIVED]


def readme_arguments():
    """The README paragraph of robot.launch's arguments ("Arguments: ...")."""
    text = (REPO / 'README.md').read_text()
    section = text[text.index('## On your robot'):text.index('**Required TF.**')]
    return section[section.index('Arguments:'):]


def nodes_md_robot_launch():
    text = (REPO / 'docs' / 'nodes.md').read_text()
    section = text[text.index('## robot.launch'):]
    return section[:section.index('Which value a node gets')]


@pytest.mark.parametrize('where, text', [('README.md', readme_arguments()),
                                         ('docs/nodes.md', nodes_md_robot_launch())])
def test_every_robot_launch_argument_is_documented(where, text):
    named = set(re.findall(r'`([a-z_]+)`', text))
    missing = [name for name in launch_args() if name not in named]
    assert not missing, '%s does not name robot.launch arguments %s' % (where, missing)


def test_every_playback_launch_argument_is_documented():
    text = (REPO / 'docs' / 'tools.md').read_text()
    paragraph = text[text.index('**`playback.launch`**'):text.index('**`bag_detect`**')]
    named = set(re.findall(r'`([a-z_]+):=', paragraph))
    missing = [name for name in launch_args('playback.launch') if name not in named]
    assert not missing, 'tools.md does not name playback.launch arguments %s' % missing
