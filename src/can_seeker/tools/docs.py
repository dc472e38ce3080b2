"""docs: write the generated documentation from the code and the result files.

``rosrun can_seeker docs`` writes docs/parameters.md (every node's parameters, from their
declarations), docs/results.md (every file in docs/results/) and the summary table between the
results markers of README.md (left alone when it has none). ``--check`` writes nothing and exits
1 when a file differs from what would be written.
"""
import argparse
import importlib
import pathlib
import re
import sys
from typing import Dict, List

from can_seeker.docs_reference import Declaration, declared_groups, parameter_reference
from can_seeker.evaluation.result_files import (load_results, readme_table, results_markdown,
                                                with_readme_table)

NODE_SCRIPT = re.compile(r'from (can_seeker\.nodes\.\w+) import main')


def node_params(root: pathlib.Path) -> List[Declaration]:
    """(script name, PARAMS) of every script under ``root``/scripts that runs a node module
    declaring its parameters, by script name."""
    found = []
    for script in sorted((root / 'scripts').glob('*')):
        match = NODE_SCRIPT.search(script.read_text())
        if match:
            module = importlib.import_module(match.group(1))
            if hasattr(module, 'PARAMS'):
                found.append((script.name, module.PARAMS))
    return found


def generated_files(root: pathlib.Path) -> Dict[str, str]:
    """{path under ``root``: the text the generator writes there}."""
    results = load_results(root / 'docs' / 'results')
    files = {'docs/parameters.md': parameter_reference(
                 node_params(root), declared_groups(root / 'src' / 'can_seeker')),
             'docs/results.md': results_markdown(results)}
    readme = root / 'README.md'
    if readme.exists():
        files['README.md'] = with_readme_table(readme.read_text(), readme_table(results))
    return files


def package_root() -> pathlib.Path:
    import rospkg  # only without --root: finding the package crawls ROS_PACKAGE_PATH
    return pathlib.Path(rospkg.RosPack().get_path('can_seeker'))


def main(argv=None):
    parser = argparse.ArgumentParser(prog='docs', description=__doc__.split('\n\n')[0])
    parser.add_argument('--root', type=pathlib.Path,
                        help='the can_seeker source checkout (default: the package ROS finds)')
    parser.add_argument('--check', action='store_true',
                        help='write nothing; exit 1 when a generated file is out of date')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    root = args.root or package_root()
    if not (root / 'scripts').is_dir() or not (root / 'src' / 'can_seeker').is_dir():
        parser.error('%s is not a can_seeker source checkout (an install space has no docs); '
                     'pass --root' % root)
    stale = []
    for relative, text in generated_files(root).items():
        path = root / relative
        if path.exists() and path.read_text() == text:
            continue
        stale.append(relative)
        if not args.check:
            path.write_text(text)
    verb = 'out of date' if args.check else 'written'
    print('docs: %s' % ('%s %s' % (', '.join(stale), verb) if stale else 'up to date'))
    sys.exit(1 if args.check and stale else 0)
