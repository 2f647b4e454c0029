#!/usr/bin/env bash
# Makes catkin_ws/src/art2part the package as ROS sees it: a folder of links to the repository's top-level entries,
# all but the workspace itself (and out/, build/). ROS walks a package's folder following links (roslaunch's and
# rosrun's file search); a link from inside the workspace back to the repository root would make that walk loop
# through catkin_ws/src/art2part/catkin_ws/... and find every launch file and node ~40 times.
# Idempotent; `--check` only reports missing or stray links (exit 1), for the tests.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
pkg="$root/catkin_ws/src/art2part"
check=false
[ "${1:-}" = "--check" ] && check=true

excluded() { case "$1" in catkin_ws|out|build) return 0 ;; *) return 1 ;; esac; }

if [ -L "$pkg" ]; then  # the old layout: one link to the root
  $check && { echo "link-workspace: $pkg is a link to the repository root (run scripts/link-workspace.sh)"; exit 1; }
  rm "$pkg"
fi
$check || mkdir -p "$pkg"
status=0
for entry in "$root"/*; do
  name=$(basename "$entry")
  excluded "$name" && continue
  target="../../../$name"
  if [ "$(readlink "$pkg/$name" 2>/dev/null)" != "$target" ]; then
    if $check; then echo "link-workspace: missing link catkin_ws/src/art2part/$name -> $target"; status=1
    else ln -sfn "$target" "$pkg/$name"; fi
  fi
done
for link in "$pkg"/*; do  # links whose entry went away
  [ -e "$link" ] && continue
  if $check; then echo "link-workspace: dangling link $link"; status=1; else rm -f "$link"; fi
done
exit $status
