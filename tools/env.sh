# Source this file for a terminal where roslaunch/rosrun/rostest/rostopic/rosbag work with
# can_seeker and nodes run the venv interpreter:   source tools/env.sh
# shellcheck source=paths.sh
. "$(dirname "${BASH_SOURCE[0]}")/paths.sh"
if [ ! -f "$CAN_SEEKER_WS/devel/setup.bash" ]; then
  echo "can_seeker: no workspace at $CAN_SEEKER_WS; run 'make setup' first" >&2
  return 1 2>/dev/null || exit 1
fi
case $- in *u*) _can_seeker_u=1; set +u ;; *) _can_seeker_u= ;; esac
# shellcheck disable=SC1091
. "$CAN_SEEKER_WS/devel/setup.bash"
[ -n "$_can_seeker_u" ] && set -u
unset _can_seeker_u
export PATH="$CAN_SEEKER_VENV/bin:$PATH"
export VIRTUAL_ENV="$CAN_SEEKER_VENV"
export ROS_HOME="${ROS_HOME:-$CAN_SEEKER_HOME/ros_home}"
export ROS_HOSTNAME="${ROS_HOSTNAME:-127.0.0.1}"
export ROS_MASTER_URI="${ROS_MASTER_URI:-http://127.0.0.1:11311}"
export PYTHONDONTWRITEBYTECODE=1
mkdir -p "$ROS_HOME"
