#!/usr/bin/env bash
# A picture of the cell in rviz, headless (Xvfb, Mesa's llvmpipe): cell.launch with rviz:=true on PART, plan_setups
# so the setup frames show, then a screenshot of the virtual screen (imagemagick's import). For `make demo`.
# Usage: rviz_screenshot.sh OUT.png PART [MACHINE]      (about 30 s)
set -eo pipefail
out=$1 part=$2 machine=${3:-vmc_3axis}
root=$(cd "$(dirname "$0")/.." && pwd)
for tool in xvfb-run import rviz; do
  command -v "$tool" >/dev/null || { echo "rviz_screenshot: $tool is missing (scripts/debian-packages.txt)"; exit 1; }
done
if [ -z "${ART2PART_IN_XVFB:-}" ]; then
  exec env ART2PART_IN_XVFB=1 xvfb-run -a -s "-screen 0 1280x960x24" "$0" "$@"
fi
export PATH=/usr/bin:/bin:$PATH
unset ROS_IP ROS_HOSTNAME
source "$root/catkin_ws/devel/setup.bash"
port=$((11700 + RANDOM % 500))
while ss -ltn 2>/dev/null | grep -q ":$port "; do port=$((11700 + RANDOM % 500)); done
export ROS_MASTER_URI=http://localhost:$port  # a master of its own
log=$(mktemp)
args=(machine:="$machine" part:="$part" rviz:=true supervisor:=false)
[ -f "$root/launch/folders.launch" ] || args+=(folders:=false)
roslaunch art2part cell.launch "${args[@]}" >"$log" 2>&1 &
launch=$!
trap 'kill -INT $launch 2>/dev/null; wait $launch 2>/dev/null; rm -f "$log"' EXIT
fail() { echo "rviz_screenshot: $*"; tail -20 "$log"; exit 1; }

for _ in $(seq 120); do  # the part loaded (STEP tessellation takes a few seconds)
  parts=$(rosservice call /list_parts 2>/dev/null) || parts=""
  [ -n "$parts" ] && ! grep -q 'part_ids: \[\]' <<<"$parts" && break
  kill -0 $launch 2>/dev/null || fail "cell.launch ended"
  sleep 0.5
done
rosservice call /plan_setups "{mode: 3axis, level: 2}" >/dev/null || fail "plan_setups failed"
for _ in $(seq 60); do  # rviz up and drawing
  rosnode list 2>/dev/null | grep -q '^/rviz$' && break
  sleep 0.5
done
sleep 6  # rviz's first frames with the markers and the frames
import -window root "$out" || fail "import failed"
echo "rviz_screenshot: $out"
