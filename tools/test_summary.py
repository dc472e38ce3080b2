#!/usr/bin/env python3
"""Sum up the JUnit XML results of one test run: print failures and 'N passed, N failed'.

Usage: test_summary.py RESULTS_DIR EXPECTED_RESULT_FILE... Counts every result file in
RESULTS_DIR, as catkin_test_results does. Exits non-zero on any failure, error, unreadable or
empty result, or an expected result file that the run did not write (a test that never ran counts
as failed).
"""
import os
import sys
import xml.etree.ElementTree as ET


def count_results(path):
    """Return (passed, failed, skipped, failure texts) for one JUnit XML file."""
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == 'testsuite' else root.iter('testsuite')
    passed = failed = skipped = 0
    problems = []
    for suite in suites:
        for case in suite.iter('testcase'):
            bad = case.find('failure')
            if bad is None:
                bad = case.find('error')
            if bad is not None:
                failed += 1
                text = (bad.get('message') or '') + '\n' + (bad.text or '')
                problems.append('%s.%s: %s' % (case.get('classname'), case.get('name'), text.strip()))
            elif case.find('skipped') is not None:
                skipped += 1
            else:
                passed += 1
    return passed, failed, skipped, problems


def main():
    results_dir, expected = sys.argv[1], sys.argv[2:]
    passed = failed = skipped = 0
    for name in expected:
        if not os.path.exists(os.path.join(results_dir, name)):
            failed += 1
            print('FAILED %s: no result written (the test did not run or crashed)' % name)
    for name in sorted(os.listdir(results_dir)) if os.path.isdir(results_dir) else []:
        if not name.endswith('.xml'):
            continue
        try:
            file_passed, file_failed, file_skipped, problems = count_results(
                os.path.join(results_dir, name))
        except ET.ParseError as error:
            failed += 1
            print('FAILED %s: unreadable result (%s)' % (name, error))
            continue
        if name.startswith('rostest-'):
            # rostest's own record: one case per <test>, passing whenever the test node ran; the
            # node's real cases are in the rosunit-*.xml files it wrote.
            file_passed = file_skipped = 0
        elif file_passed + file_failed + file_skipped == 0:
            failed += 1
            print('FAILED %s: no test case ran' % name)
        for problem in problems:
            print('FAILED %s\n  %s' % (name, problem[:4000].replace('\n', '\n  ')))
        passed += file_passed
        failed += file_failed
        skipped += file_skipped
        print('%-46s %3d passed, %d failed' % (name, file_passed, file_failed))
    line = '%d passed, %d failed' % (passed, failed)
    if skipped:
        line += ', %d skipped' % skipped
    print(line)
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
