"""Every node parameter is declared once (PARAMS), mirrored as a documented launch arg with the
same default, and listed in the README table."""
import importlib
import pathlib
import re
import xml.etree.ElementTree as ET

import pytest

from can_seeker.params import launch_value

ROOT = pathlib.Path(__file__).resolve().parents[2]


def node_modules():
    """(script name, module) for every script that is a node with declared PARAMS."""
    found = []
    for script in sorted((ROOT / 'scripts').glob('*')):
        match = re.search(r'from (can_seeker\.nodes\.\w+) import main', script.read_text())
        if match:
            module = importlib.import_module(match.group(1))
            if hasattr(module, 'PARAMS'):
                found.append((script.name, module))
    return found


def launch_nodes(script_name):
    """(launch file, <node> element, {arg name: <arg> element}) for each launch of that script."""
    for launch in sorted((ROOT / 'launch').glob('*.launch')):
        root = ET.parse(launch).getroot()
        args = {arg.get('name'): arg for arg in root.findall('arg')}  # not an <include>'s
        for node in root.iter('node'):
            if node.get('pkg') == 'can_seeker' and node.get('type') == script_name:
                yield launch.name, node, args


NODES = node_modules()


def test_there_are_nodes_to_check():
    assert {name for name, _ in NODES} >= {'sim_node', 'image_converter', 'can_stopper'}


@pytest.mark.parametrize('script_name,module', NODES, ids=[name for name, _ in NODES])
def test_launch_args_mirror_the_declared_defaults(script_name, module):
    launches = list(launch_nodes(script_name))
    assert launches, 'no launch file starts %s' % script_name
    for launch_name, node, args in launches:
        params = {p.get('name'): p.get('value') for p in node.iter('param')}
        for spec in module.PARAMS:
            where = '%s: ~%s' % (launch_name, spec.name)
            assert spec.name in params, where + ' is not passed to the node'
            value = params[spec.name]
            arg_match = re.fullmatch(r'\$\(arg (\w+)\)', value or '')
            assert arg_match, where + ' should come from an <arg>'
            arg = args.get(arg_match.group(1))
            assert arg is not None, where + ' uses an undeclared arg'
            assert arg.get('default') == launch_value(spec.default), where + ' default differs'
            assert (arg.get('doc') or '').strip(), where + ' arg has no doc='


@pytest.mark.parametrize('script_name,module', NODES, ids=[name for name, _ in NODES])
def test_readme_documents_every_parameter(script_name, module):
    readme = (ROOT / 'README.md').read_text()
    for spec in module.PARAMS:
        default = launch_value(spec.default) or '""'
        row = '| `~%s` | `%s` |' % (spec.name, default)
        assert row in readme, 'README lacks the row for %s ~%s' % (script_name, spec.name)


@pytest.mark.parametrize('script_name,module', NODES, ids=[name for name, _ in NODES])
def test_safety_bounds_say_so_in_the_readme_and_launch_file(script_name, module):
    """The README row and the node's own launch file show a safety bound's safe side."""
    readme = (ROOT / 'README.md').read_text()
    for spec in module.PARAMS:
        if spec.safer is None:
            continue
        row = '| `~%s` | `%s` | %s |' % (spec.name, launch_value(spec.default), spec.description)
        assert row in readme, 'README row of %s ~%s lacks its safe side' % (script_name, spec.name)
        launch = ET.parse(ROOT / 'launch' / ('%s.launch' % script_name)).getroot()
        docs = {arg.get('name'): arg.get('doc') for arg in launch.iter('arg')}
        assert docs[spec.name] == spec.description, '%s.launch: ~%s' % (script_name, spec.name)
