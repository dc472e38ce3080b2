#!/usr/bin/env python3
"""Run catkin_lint on the package and write the outcome as a JUnit XML test result.

Usage: catkin_lint_junit.py PACKAGE_DIR RESULT_XML. Any catkin_lint message (error, warning or
notice) fails the test, so the package stays lint-clean.
"""
import subprocess
import sys
from xml.sax.saxutils import escape, quoteattr


def main():
    package_dir, result_xml = sys.argv[1], sys.argv[2]
    run = subprocess.run(['catkin_lint', '-W2', '--strict', package_dir],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    output = run.stdout.strip()
    failed = run.returncode != 0
    body = ''
    if failed:
        body = '<failure message=%s>%s</failure>' % (quoteattr('catkin_lint reported problems'),
                                                      escape(output))
    with open(result_xml, 'w') as xml:
        xml.write('<?xml version="1.0" encoding="utf-8"?>\n'
                  '<testsuite name="catkin_lint" tests="1" failures="%d" errors="0">'
                  '<testcase classname="lint" name="catkin_lint">%s</testcase></testsuite>\n'
                  % (int(failed), body))
    print(output or 'catkin_lint: clean')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
