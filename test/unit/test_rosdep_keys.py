"""Every dependency in package.xml is a real rosdep key, so `rosdep install --from-paths src
--ignore-src -y` resolves all of them: either a ROS package (its name is its key) or a system key
listed, with its rosdistro definition, in test/data/rosdep_keys.yaml. Needs no network."""
import pathlib

import pytest
import rospkg
import yaml
from catkin_pkg.package import parse_package

REPO = pathlib.Path(__file__).resolve().parents[2]
ROSDEP_KEYS = yaml.safe_load((REPO / 'test' / 'data' / 'rosdep_keys.yaml').read_text())
KEYS = ROSDEP_KEYS['keys']
WITHOUT_KEY = ROSDEP_KEYS['without_key']
INSTALLER_FIELDS = {'apt', 'pip', 'packages', 'source'}
PLATFORMS = {'focal': ('ubuntu', 'focal'), 'bookworm': ('debian', 'bookworm')}
ROSPACK = rospkg.RosPack()


def dependency_names(package_xml):
    """Every dependency name of one package.xml, of every kind (build, exec, test, ...)."""
    package = parse_package(str(package_xml))
    groups = (package.buildtool_depends, package.build_depends, package.build_export_depends,
              package.buildtool_export_depends, package.exec_depends, package.test_depends,
              package.doc_depends)
    return sorted({dependency.name for group in groups for dependency in group})


def is_ros_package(name):
    try:
        ROSPACK.get_path(name)
    except rospkg.ResourceNotFound:
        return False
    return True


def unknown_keys(names):
    """The names that are neither an installed ROS package nor a listed rosdep key."""
    return [name for name in names if name not in KEYS and not is_ros_package(name)]


def resolve(definition, os_name, codename):
    """What rosdep installs for one key definition on one OS release: {'apt'|'pip': [...]}, or
    None where the key has no rule for that release."""
    rule = definition.get(os_name)
    if isinstance(rule, dict) and not INSTALLER_FIELDS & rule.keys():
        rule = rule.get(codename, rule.get('*'))
    if rule is None:
        return None
    if isinstance(rule, list):
        return {'apt': rule}
    if 'pip' in rule:
        return {'pip': rule['pip']['packages']}
    return {'apt': rule['packages']}


def package_xmls():
    return sorted(p for p in REPO.glob('**/package.xml')
                  if '.git' not in p.parts and 'test' not in p.relative_to(REPO).parts)


def test_the_repository_has_its_package_xml():
    assert REPO / 'package.xml' in package_xmls()


@pytest.mark.parametrize('package_xml', package_xmls(), ids=lambda p: str(p.relative_to(REPO)))
def test_every_dependency_is_a_rosdep_key(package_xml):
    names = dependency_names(package_xml)
    assert 'rospy' in names or 'roscpp' in names
    assert unknown_keys(names) == []


def test_a_python_module_name_is_not_a_rosdep_key():
    assert unknown_keys(['catkin_lint', 'pybullet', 'rospy', 'python3-catkin-lint']) == [
        'catkin_lint', 'pybullet']


@pytest.mark.parametrize('key', sorted(KEYS))
def test_listed_key_resolves_as_its_rosdistro_definition_says(key):
    entry = KEYS[key]
    assert entry['file'] in ('rosdep/base.yaml', 'rosdep/python.yaml')
    definition = yaml.safe_load(entry['definition'])
    assert list(definition) == [key]
    for release, (os_name, codename) in PLATFORMS.items():
        assert resolve(definition[key], os_name, codename) == entry[release], release


def test_release_rules_override_the_default():
    definition = {'debian': {'*': ['pkg'], 'buster': None},
                  'ubuntu': {'*': ['pkg'], 'focal': {'pip': {'packages': ['pkg-pip']}}}}
    assert resolve(definition, 'debian', 'bookworm') == {'apt': ['pkg']}
    assert resolve(definition, 'debian', 'buster') is None
    assert resolve(definition, 'ubuntu', 'focal') == {'pip': ['pkg-pip']}
    assert resolve(definition, 'fedora', '39') is None


def listed_lines(path):
    return [line.strip() for line in (REPO / path).read_text().splitlines()
            if line.strip() and not line.startswith('#')]


@pytest.mark.parametrize('module', sorted(WITHOUT_KEY))
def test_a_module_without_a_rosdep_key_comes_from_apt_and_pip_instead(module):
    apt_name, pip_name = WITHOUT_KEY[module]['apt'], WITHOUT_KEY[module]['pip']
    assert not {module, apt_name, pip_name} & set(dependency_names(REPO / 'package.xml'))
    assert apt_name not in KEYS
    assert apt_name in listed_lines('tools/apt-packages.txt')
    assert [line for line in listed_lines('requirements.txt')
            if line.startswith(pip_name + '==')]
