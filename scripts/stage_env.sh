#!/usr/bin/env bash
# roslaunch env-loader for the stage host (cell.launch's stage_env_loader): runs COMMAND in this workspace's ROS
# environment with ROS_IP set to this host's address, so that the nodes it starts are reachable from the other hosts
# (without it, sourcing setup.bash keeps ROS on loopback). ROS_IP or ROS_HOSTNAME already set wins; otherwise the
# first address `hostname -I` lists. Usage: stage_env.sh COMMAND [ARGS...]
if [ -z "${ROS_IP:-}" ] && [ -z "${ROS_HOSTNAME:-}" ]; then
  ROS_IP=$(hostname -I 2>/dev/null | awk '{print $1}')
  [ -n "$ROS_IP" ] && export ROS_IP
fi
root=$(cd -P "$(dirname "$0")" && cd .. && pwd)  # the repository, also when run through the package folder's links
if [ -f "$root/catkin_ws/devel/setup.bash" ]; then
  source "$root/catkin_ws/devel/setup.bash"
else
  source "$root/catkin_ws/install/setup.bash"
fi
exec "$@"
