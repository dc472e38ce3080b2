"""The nodes whose ``--param`` overrides evaluate checks are the nodes demo.launch starts for
it, each checked against the very tuple the node reads and the reference documents."""
import pathlib

import pytest
import roslaunch.config
import roslaunch.xmlloader

from can_seeker.evaluation.sweep import EVALUATED_NODES
from can_seeker.tools import evaluate
from can_seeker.tools.docs import node_params

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEMO_LAUNCH = ROOT / 'launch' / 'demo.launch'


def started_nodes(launch_args):
    """{node name: (namespace, script)} of the can_seeker nodes demo.launch starts with these
    arguments (roslaunch's own reading of the file, nothing started)."""
    config = roslaunch.config.ROSLaunchConfig()
    argv = ['roslaunch', str(DEMO_LAUNCH)] + ['%s:=%s' % item for item in launch_args.items()]
    roslaunch.xmlloader.XmlLoader().load(str(DEMO_LAUNCH), config, argv=argv, verbose=False)
    return {node.name: (node.namespace, node.type) for node in config.nodes
            if node.package == 'can_seeker'}


OTHER_OPTIONS = ['--world', 'empty', '--scan-topics', '', '--no-lockstep', '--robot',
                 'turtlebot3_burger', '--randomize-mount']


@pytest.mark.parametrize('options', [[], OTHER_OPTIONS], ids=['defaults', 'other-options'])
def test_the_checked_nodes_are_those_the_closed_loop_starts(options):
    nodes = started_nodes(evaluate.launch_args(evaluate.parse_args(options)))
    assert set(nodes) == set(EVALUATED_NODES)
    assert {namespace for namespace, _ in nodes.values()} == {'/'}


def test_each_checked_node_is_checked_against_the_parameters_it_reads():
    read = dict(node_params(ROOT))
    for name, (_, script) in started_nodes(evaluate.launch_args(evaluate.parse_args([]))).items():
        assert EVALUATED_NODES[name] is read[script], name

