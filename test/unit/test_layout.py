"""The package layout: pure subpackages never import ROS (the ROS edge is ``ros/``, used by the
nodes and tools), no node imports another node, the simulator does not import the controller,
every folder is an installable package, and module docstrings stay short."""
import ast
import pathlib

PACKAGE = pathlib.Path(__file__).resolve().parents[2] / 'src' / 'can_seeker'
ROS_GLUE = {'nodes', 'tools', 'ros'}
ROS_MODULES = {'rospy', 'rosbag', 'rosgraph', 'roslaunch', 'rostest', 'tf2_ros', 'cv_bridge',
               'dynamic_reconfigure', 'sensor_msgs', 'geometry_msgs', 'std_msgs', 'nav_msgs',
               'diagnostic_updater', 'diagnostic_msgs', 'visualization_msgs', 'rospkg'}


def imported_modules(path):
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module


def imported_top_levels(path):
    return (name.split('.')[0] for name in imported_modules(path))


def subpackage_imports(folder, prefix):
    """{module file: the can_seeker modules starting with ``prefix`` it imports} of every
    module in ``folder`` that imports any."""
    found = {}
    for path in sorted((PACKAGE / folder).rglob('*.py')):
        hits = sorted(name for name in imported_modules(path) if name.startswith(prefix))
        if hits:
            found[str(path.relative_to(PACKAGE))] = hits
    return found


def test_pure_modules_import_no_ros():
    pure = [p for p in PACKAGE.rglob('*.py') if p.relative_to(PACKAGE).parts[0] not in ROS_GLUE]
    assert len(pure) > 10
    offenders = {str(p.relative_to(PACKAGE)): sorted(set(imported_top_levels(p)) & ROS_MODULES)
                 for p in pure}
    assert {k: v for k, v in offenders.items() if v} == {}


def test_every_source_folder_is_a_package():
    folders = {p.parent for p in PACKAGE.rglob('*.py')}
    assert {f for f in folders if not (f / '__init__.py').exists()} == set()
    assert {'sim', 'vision', 'control', 'evaluation', 'nodes', 'tools'} <= {
        f.name for f in folders}


def test_no_node_imports_another_node():
    """Shared ROS code lives in ros/; a node module is wiring of its own."""
    assert subpackage_imports('nodes', 'can_seeker.nodes') == {}


def test_the_simulator_does_not_import_the_controller():
    assert subpackage_imports('sim', 'can_seeker.control') == {}



MAX_MODULE_DOCSTRING_LINES = 30
"""A module docstring states the contract; the design and its reasons live in docs/design/."""


def test_module_docstrings_state_a_contract_not_a_design_note():
    long = {}
    for path in sorted(PACKAGE.rglob('*.py')):
        docstring = ast.get_docstring(ast.parse(path.read_text(), str(path)), clean=False)
        if docstring and docstring.count('\n') + 1 > MAX_MODULE_DOCSTRING_LINES:
            long[str(path.relative_to(PACKAGE))] = docstring.count('\n') + 1
    assert long == {}


def test_the_controller_does_not_import_the_simulator():
    assert subpackage_imports('control', 'can_seeker.sim') == {}
