# Sourced with the workspace's setup (catkin env hook). ROS 1 has no authentication: whoever reaches the master can
# call every service. Unless this host's address is set (ROS_IP or ROS_HOSTNAME), the master and the nodes advertise
# and listen on loopback only. On a cell network: export ROS_IP=<this host's address> (README, "The cell").
if [ -z "${ROS_IP:-}" ] && [ -z "${ROS_HOSTNAME:-}" ]; then
  export ROS_IP=127.0.0.1
fi
