#!/usr/bin/env bash
# Runs multi_host.test in a network namespace of its own whose loopback carries the addresses 10.77.0.1-4, one per
# "host": the master on .1, part_server on .2, the client on .3, setup_planner on .4. Not 127.0.0.x: roscpp listens on
# 127.0.0.1 alone whenever ROS_IP is any 127.x address, so a node advertising 127.0.0.2 cannot be reached at all.
# Usage: multi_host.sh DEVEL_PREFIX. Exit 77 (skipped) where no network namespace can be made.
set -eo pipefail
devel=$1
if [ "${2:-}" != --inside ]; then
  for flags in "--net" "--net --map-root-user"; do
    # shellcheck disable=SC2086
    if unshare $flags true 2>/dev/null; then exec unshare $flags "$0" "$devel" --inside; fi
  done
  echo "multi_host: cannot make a network namespace here (unshare --net): skipped"
  exit 77
fi
ip link set lo up
for host in 1 2 3 4; do ip addr add "10.77.0.$host/32" dev lo; done
export PATH=/usr/bin:/bin:$PATH
unset ROS_HOSTNAME
source "$devel/setup.bash"
export ROS_IP=10.77.0.1
exec rostest art2part multi_host.test
