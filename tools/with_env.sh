#!/usr/bin/env bash
# Run one command inside the can_seeker environment (see env.sh).
set -eu
# shellcheck source=env.sh
. "$(dirname "$0")/env.sh"
exec "$@"
