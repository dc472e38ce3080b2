"""Every node parameter is declared once (PARAMS), mirrored as a documented launch arg with the
same default, and listed in the generated reference, docs/parameters.md, as the code declares it
now."""
import pathlib
import re
import xml.etree.ElementTree as ET

import pytest

from can_seeker.docs_reference import declared_groups, parameter_reference
from can_seeker.params import by_namespace, launch_value
from can_seeker.tools.docs import node_params

ROOT = pathlib.Path(__file__).resolve().parents[2]
REFERENCE = ROOT / 'docs' / 'parameters.md'


def launch_nodes(script_name):
    """(launch file, <node> element, {arg name: <arg> element}) for each launch of that script."""
    for launch in sorted((ROOT / 'launch').glob('*.launch')):
        root = ET.parse(launch).getroot()
        args = {arg.get('name'): arg for arg in root.findall('arg')}  # not an <include>'s
        for node in root.iter('node'):
            if node.get('pkg') == 'can_seeker' and node.get('type') == script_name:
                yield launch.name, node, args


NODES = node_params(ROOT)


def test_there_are_nodes_to_check():
    assert {name for name, _ in NODES} >= {'sim_node', 'image_converter', 'can_stopper'}


@pytest.mark.parametrize('script_name,params', NODES, ids=[name for name, _ in NODES])
def test_launch_args_mirror_the_declared_defaults(script_name, params):
    launches = list(launch_nodes(script_name))
    assert launches, 'no launch file starts %s' % script_name
    for launch_name, node, args in launches:
        passed = {p.get('name'): p.get('value') for p in node.iter('param')}
        for spec in params:
            where = '%s: ~%s' % (launch_name, spec.name)
            assert spec.name in passed, where + ' is not passed to the node'
            value = passed[spec.name]
            arg_match = re.fullmatch(r'\$\(arg (\w+)\)', value or '')
            assert arg_match, where + ' should come from an <arg>'
            arg = args.get(arg_match.group(1))
            assert arg is not None, where + ' uses an undeclared arg'
            assert arg.get('default') == launch_value(spec.default), where + ' default differs'
            assert (arg.get('doc') or '').strip(), where + ' arg has no doc='


def reference_order(params):
    """``params`` in the order the reference lists them: the top first, then each namespace's
    table."""
    return [spec for _, group in by_namespace(params) for spec in group]


def reference_section(script_name):
    """The rows of the reference's section of that node (its namespaces' tables too)."""
    sections = re.split(r'^## ', REFERENCE.read_text(), flags=re.MULTILINE)
    section = next(text for text in sections if text.startswith(script_name + '\n'))
    return [line for line in section.splitlines() if line.startswith('| `~')]


def test_the_reference_is_what_the_code_declares_now():
    expected = parameter_reference(node_params(ROOT), declared_groups(ROOT / 'src' / 'can_seeker'))
    assert REFERENCE.read_text() == expected, \
        'docs/parameters.md is out of date: run rosrun can_seeker docs'


@pytest.mark.parametrize('script_name,params', NODES, ids=[name for name, _ in NODES])
def test_the_reference_documents_every_parameter(script_name, params):
    rows = reference_section(script_name)
    assert len(rows) == len(params)
    for spec, row in zip(reference_order(params), rows):
        default = launch_value(spec.default) or '""'
        assert row.startswith('| `~%s` | %s | `%s` |' % (spec.name, type(spec.default).__name__,
                                                         default)), row


@pytest.mark.parametrize('script_name,params', NODES, ids=[name for name, _ in NODES])
def test_safety_bounds_say_so_in_the_reference_and_launch_file(script_name, params):
    """The reference row and the node's own launch file show a safety bound's safe side."""
    rows = dict(zip((spec.name for spec in reference_order(params)),
                    reference_section(script_name)))
    for spec in params:
        safe_side = rows[spec.name].split(' | ')[5]
        assert safe_side == (spec.safer or ''), '%s ~%s' % (script_name, spec.name)
        if spec.safer is None:
            continue
        launch = ET.parse(ROOT / 'launch' / ('%s.launch' % script_name)).getroot()
        docs = {arg.get('name'): arg.get('doc') for arg in launch.iter('arg')}
        assert docs[spec.name] == spec.description, '%s.launch: ~%s' % (script_name, spec.name)
