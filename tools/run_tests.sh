#!/usr/bin/env bash
# Run every test the way ROS CI does (catkin_make run_tests, two at a time), then sum up the
# JUnit results: unit tests (pytest), catkin_lint, the package tests (roslaunch-check, install
# space) and each rostest. The line after 'N passed, N failed' is the whole run's time, from
# CAN_SEEKER_TEST_START_S (epoch s; make test sets it before the setup) or this script's start.
set -eu
whole_start=${CAN_SEEKER_TEST_START_S:-$(date +%s)}
# shellcheck source=env.sh
. "$(dirname "$0")/env.sh"
cd "$CAN_SEEKER_REPO"
results="$CAN_SEEKER_WS/build/test_results/can_seeker"
log="$CAN_SEEKER_HOME/run_tests.log"
rm -rf "$results"
expected=(pytest-unit.xml lint-catkin_lint.xml)
for test_file in test/package/test_*.py; do
  [ -e "$test_file" ] && expected+=("pytest-$(basename "$test_file" .py | sed 's/^test_//').xml")
done
for test_file in test/*.test; do
  [ -e "$test_file" ] && expected+=("rostest-test_$(basename "$test_file" .test).xml")
done
echo "test: running ${#expected[@]} test targets (log: $log)"
start=$(date +%s)
make -C "$CAN_SEEKER_WS/build" -j2 run_tests >"$log" 2>&1 || true
echo "test: finished in $(( $(date +%s) - start )) s"
summary_status=0
python3 tools/test_summary.py "$results" "${expected[@]}" || summary_status=$?
whole_s=$(( $(date +%s) - whole_start ))
echo "test: the whole run took $(( whole_s / 60 )) min $(( whole_s % 60 )) s (setup included)"
if [ "$summary_status" -ne 0 ]; then
  echo "test: FAILED; the end of $log:"
  tail -n 60 "$log"
  exit 1
fi
