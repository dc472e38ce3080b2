#!/usr/bin/env bash
# Idempotent setup: ROS (an installed /opt/ros distribution, else Debian's packages with apt), the
# venv with pinned PyPI packages, and the catkin workspace (outside the repo). Each step is skipped
# when it is already done.
set -eu
# shellcheck source=paths.sh
. "$(dirname "$0")/paths.sh"
cd "$CAN_SEEKER_REPO"
say() { printf 'setup: %s\n' "$*"; }
mkdir -p "$CAN_SEEKER_HOME"
log="$CAN_SEEKER_HOME/setup.log"
exec 9>"$CAN_SEEKER_HOME/setup.lock"
flock 9

# 1. ROS and the system packages. An installed ROS 1 (/opt/ros/<distro>/setup.bash, noetic
#    first; CAN_SEEKER_ROS_ROOT replaces /opt/ros) is used as it is: sourced for the build, its
#    missing dependencies installed by rosdep. Without one, ROS 1 comes from Debian's own packages
#    (tools/apt-packages.txt).
ros_setup=""
for candidate in "${CAN_SEEKER_ROS_ROOT:-/opt/ros}"/noetic/setup.bash "${CAN_SEEKER_ROS_ROOT:-/opt/ros}"/*/setup.bash; do
  # A catkin prefix (ROS 1) has a .catkin marker; ROS 2 installations have none.
  if [ -f "$candidate" ] && [ -f "$(dirname "$candidate")/.catkin" ]; then
    ros_setup=$candidate
    break
  fi
done
if [ -n "$ros_setup" ]; then
  say "using the installed ROS at $(dirname "$ros_setup") (tools/apt-packages.txt not needed)"
  set +u
  # shellcheck disable=SC1090
  . "$ros_setup"
  set -u
  # pybullet comes from requirements.txt into the venv: rosdep's pip key would install the newest
  # one system-wide, which Python 3.8 with numpy 1.17 (Noetic on Ubuntu 20.04) cannot import.
  rosdep_args=(--from-paths "$CAN_SEEKER_REPO" --ignore-src --skip-keys=python3-pybullet-pip)
  if ! command -v rosdep >/dev/null; then
    say "rosdep not found: install python3-rosdep, then: rosdep install ${rosdep_args[*]} -y"
  elif rosdep check "${rosdep_args[@]}" >>"$log" 2>&1; then
    say "rosdep: every system dependency is installed"
  else
    say "rosdep: missing dependencies; running: rosdep install ${rosdep_args[*]} -y"
    as_root=()
    [ "$(id -u)" -ne 0 ] || as_root=(--as-root apt:false)  # root (e.g. a container) needs no sudo
    rosdep install "${rosdep_args[@]}" "${as_root[@]}" -y >>"$log" 2>&1 \
      || { tail -n 30 "$log"; say "rosdep install failed (log: $log; a new rosdep needs 'sudo rosdep init' and 'rosdep update')"; exit 1; }
  fi
else
  mapfile -t wanted < <(grep -v '^\s*\(#\|$\)' tools/apt-packages.txt)
  missing=()
  for pkg in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed' || missing+=("$pkg")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    say "installing ${#missing[@]} Debian packages: ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >>"$log" 2>&1 \
      || { tail -n 30 "$log"; say "apt-get install failed (log: $log)"; exit 1; }
  else
    say "Debian packages: all ${#wanted[@]} installed"
  fi
fi

# 2. The venv (sees the system's rospy, cv_bridge, OpenCV, numpy) with pinned PyPI packages.
req_stamp="$CAN_SEEKER_VENV/.requirements.sha1"
req_sum=$(sha1sum requirements.txt | cut -d' ' -f1)
if [ ! -x "$CAN_SEEKER_VENV/bin/python3" ] || [ "$(cat "$req_stamp" 2>/dev/null)" != "$req_sum" ]; then
  say "creating the venv at $CAN_SEEKER_VENV"
  /usr/bin/python3 -m venv --system-site-packages "$CAN_SEEKER_VENV" \
    || { say "python3 -m venv failed: install python3-venv (apt-get install python3-venv)"; exit 1; }
  "$CAN_SEEKER_VENV/bin/python3" -m pip install -q --disable-pip-version-check -r requirements.txt >>"$log" 2>&1 \
    || { tail -n 30 "$log"; say "pip install failed (log: $log)"; exit 1; }
  "$CAN_SEEKER_VENV/bin/python3" -c 'import pybullet, rospy, cv_bridge, cv2, numpy' \
    || { say "the venv cannot import pybullet/rospy/cv_bridge"; exit 1; }
  echo "$req_sum" >"$req_stamp"
else
  say "venv: up to date ($CAN_SEEKER_VENV)"
fi

# 3. The catkin workspace, with the repo linked in as src/can_seeker.
mkdir -p "$CAN_SEEKER_WS/src"
if [ "$(readlink "$CAN_SEEKER_WS/src/can_seeker" 2>/dev/null)" != "$CAN_SEEKER_REPO" ]; then
  ln -sfn "$CAN_SEEKER_REPO" "$CAN_SEEKER_WS/src/can_seeker"
fi
build_sum=$( { printf '%s\n' "$CAN_SEEKER_REPO" "$CAN_SEEKER_VENV" "$ros_setup";
  find package.xml CMakeLists.txt setup.py msg srv cfg scripts test test/package -maxdepth 1 -type f | LC_ALL=C sort;
  cat package.xml CMakeLists.txt setup.py msg/* srv/* cfg/* src/can_seeker/vision/detector.py src/can_seeker/params.py 2>/dev/null; } | sha1sum | cut -d' ' -f1)
build_stamp="$CAN_SEEKER_WS/.build.sha1"
if [ ! -f "$CAN_SEEKER_WS/devel/setup.bash" ] || [ "$(cat "$build_stamp" 2>/dev/null)" != "$build_sum" ]; then
  say "building the catkin workspace at $CAN_SEEKER_WS"
  (
    export PATH="$CAN_SEEKER_VENV/bin:$PATH"
    cd "$CAN_SEEKER_WS"
    catkin_make --force-cmake -DPYTHON_EXECUTABLE="$CAN_SEEKER_VENV/bin/python3" -DCATKIN_ENABLE_TESTING=ON \
      -DCMAKE_BUILD_TYPE=Release
  ) >>"$log" 2>&1 || { tail -n 40 "$log"; say "catkin_make failed (log: $log)"; exit 1; }
  echo "$build_sum" >"$build_stamp"
else
  say "catkin workspace: up to date ($CAN_SEEKER_WS)"
fi
say "done. For a ROS shell: make shell (or: source tools/env.sh)"
