"""Where the tools write their outputs by default: a folder in the user's ROS home, never the
working directory (run in a checkout, outputs there would lie in the package's source tree).

The home is ``$CAN_SEEKER_HOME`` when set (a checkout's workspace home, see tools/paths.sh),
else ``$ROS_HOME/can_seeker``, else ``~/.ros/can_seeker``, where ROS keeps its own logs.
"""
import os
from typing import Mapping, Optional


def output_home(environ: Optional[Mapping[str, str]] = None) -> str:
    """The folder the tools' default output folders are in (absolute)."""
    environ = os.environ if environ is None else environ
    if environ.get('CAN_SEEKER_HOME'):
        home = environ['CAN_SEEKER_HOME']
    elif environ.get('ROS_HOME'):
        home = os.path.join(environ['ROS_HOME'], 'can_seeker')
    else:
        home = os.path.join(environ.get('HOME') or os.path.expanduser('~'), '.ros', 'can_seeker')
    return os.path.abspath(os.path.expanduser(home))


def default_output_dir(name: str, environ: Optional[Mapping[str, str]] = None) -> str:
    """The default output folder ``name`` of a tool (e.g. ``demo_output``)."""
    return os.path.join(output_home(environ), name)
