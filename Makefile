# can_seeker: `make demo` and `make test` set everything up on a fresh Debian 12 machine.
SHELL := /bin/bash
.DEFAULT_GOAL := help
.PHONY: help setup test demo teleop shell bench clean
MAKE_START_S := $(shell date +%s)

help:
	@echo "make setup  - install Debian packages, the venv and build the catkin workspace (idempotent)"
	@echo "make test   - setup, then unit tests, catkin_lint and every rostest; prints 'N passed, N failed' and the whole time"
	@echo "make demo   - setup, then the headless closed-loop run (SEED=n to repeat one)"
	@echo "make teleop - setup, then drive the simulated robot by keyboard with image windows (ARGS=\"gui:=true\")"
	@echo "make shell  - setup, then a terminal where roslaunch/rosrun/rostopic/rosbag work"
	@echo "make bench  - setup, then the vision and simulator benchmarks"
	@echo "make clean  - remove the venv, workspace and logs of this checkout"

setup:
	@bash tools/setup.sh

test: setup
	@CAN_SEEKER_TEST_START_S=$(MAKE_START_S) bash tools/run_tests.sh

demo: setup
	@bash tools/with_env.sh rosrun can_seeker demo $(if $(SEED),--seed $(SEED))

teleop: setup
	@bash tools/with_env.sh roslaunch can_seeker teleop.launch $(ARGS)

shell: setup
	@bash tools/shell.sh

bench: setup
	@bash tools/with_env.sh rosrun can_seeker bench_vision
	@bash tools/with_env.sh rosrun can_seeker bench_node
	@bash tools/with_env.sh rosrun can_seeker bench_sim

clean:
	@. tools/paths.sh && echo "removing $$CAN_SEEKER_HOME" && rm -rf "$$CAN_SEEKER_HOME"
