"""The package layout: pure subpackages never import ROS, and every folder is an installable package."""
import ast
import pathlib

PACKAGE = pathlib.Path(__file__).resolve().parents[2] / 'src' / 'can_seeker'
ROS_GLUE = {'nodes', 'tools'}
ROS_MODULES = {'rospy', 'rosbag', 'rosgraph', 'roslaunch', 'rostest', 'tf2_ros', 'cv_bridge',
               'dynamic_reconfigure', 'sensor_msgs', 'geometry_msgs', 'std_msgs', 'nav_msgs',
               'diagnostic_updater', 'diagnostic_msgs'}


def imported_top_levels(path):
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name.split('.')[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module.split('.')[0]


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
