#!/usr/bin/env bash
# Run one command inside the can_seeker environment (see env.sh): bash tools/with_env.sh CMD...
set -eu
command=("$@")
# catkin's setup.bash reads the positional arguments, so source it without them.
set --
# shellcheck source=env.sh
. "$(dirname "$0")/env.sh"
exec "${command[@]}"
