#!/usr/bin/env bash
# An interactive shell inside the can_seeker environment (see env.sh).
set -eu
here=$(cd "$(dirname "$0")" && pwd -P)
exec bash --rcfile <(printf '[ -f ~/.bashrc ] && . ~/.bashrc\n. %q\nPS1="(can_seeker) $PS1"\necho "can_seeker shell: roslaunch can_seeker demo.launch, rostopic, rosbag ... (exit to leave)"\n' "$here/env.sh") -i
