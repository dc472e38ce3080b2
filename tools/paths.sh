# Where can_seeker keeps its venv, catkin workspace and ROS_HOME (sourced, not run).
# The workspace must live outside the repository; override with CAN_SEEKER_HOME,
# CAN_SEEKER_VENV or CAN_SEEKER_WS. Those inherited from another checkout's environment (a shell
# that sourced its tools/env.sh) are not this checkout's: setting up would re-point that
# checkout's workspace here.
_can_seeker_repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
if [ -n "${CAN_SEEKER_REPO:-}" ] && [ "$CAN_SEEKER_REPO" != "$_can_seeker_repo" ]; then
  unset CAN_SEEKER_HOME CAN_SEEKER_VENV CAN_SEEKER_WS
fi
CAN_SEEKER_REPO=$_can_seeker_repo
_can_seeker_key=$(printf '%s' "$CAN_SEEKER_REPO" | sha1sum | cut -c1-8)
: "${CAN_SEEKER_HOME:=${XDG_CACHE_HOME:-$HOME/.cache}/can_seeker/$(basename "$CAN_SEEKER_REPO")-$_can_seeker_key}"
: "${CAN_SEEKER_VENV:=$CAN_SEEKER_HOME/venv}"
: "${CAN_SEEKER_WS:=$CAN_SEEKER_HOME/ws}"
export CAN_SEEKER_REPO CAN_SEEKER_HOME CAN_SEEKER_VENV CAN_SEEKER_WS
unset _can_seeker_key _can_seeker_repo
