#!/usr/bin/env bash
# ROS finds the package's files by name, once each, from the devel space and from the install space:
# rospack find, roslaunch of every launch file, rosrun of the nodes, the Python messages, cell.launch's parameters and
# its <machine> tags. Usage: launch_by_name.sh DEVEL_PREFIX BUILD_DIR INSTALL_PREFIX
set -eo pipefail
devel=$1 build=$2 install=$3
here=$(cd "$(dirname "$0")" && pwd -P)
repo=$(cd "$here/../.." && pwd -P)
export PATH=/usr/bin:/bin:$PATH
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "launch_by_name: FAIL: $*"; exit 1; }

"$repo/scripts/link-workspace.sh" --check || fail "catkin_ws/src/art2part does not link every entry of the repository"

# Until the safety branch's launch/folders.launch is merged, cell.launch runs without it.
cell_args=(supervisor:=false)
[ -f "$repo/launch/folders.launch" ] || cell_args+=(folders:=false)

check_space() {  # SETUP_BASH EXPECTED_PACKAGE_DIR
  local setup=$1 expected=$2
  ( unset ROS_IP ROS_HOSTNAME
    source "$setup"
    set -u
    [ "${ROS_IP:-}" = 127.0.0.1 ] || fail "without ROS_IP or ROS_HOSTNAME, setup.bash must put ROS on loopback"
    [ "$(rospack find art2part 2>"$tmp/err")" = "$expected" ] || fail "rospack find art2part: $(rospack find art2part)"
    [ ! -s "$tmp/err" ] || fail "rospack find art2part complained: $(cat "$tmp/err")"
    for f in "$repo"/launch/*.launch; do
      name=$(basename "$f")
      args=()
      [ "$name" = cell.launch ] && args=("${cell_args[@]}")
      [ "$name" = folders.launch ] && continue
      timeout 60 roslaunch --files art2part "$name" "${args[@]}" >"$tmp/files" 2>"$tmp/err" \
        || fail "roslaunch --files art2part $name: $(cat "$tmp/err")"
      [ "$(grep -c "/launch/$name\$" "$tmp/files")" = 1 ] || fail "roslaunch art2part $name found: $(cat "$tmp/files")"
      ! grep -qi "multiple files\|loop" "$tmp/err" || fail "roslaunch art2part $name: $(cat "$tmp/err")"
    done
    for node in art2part part_server_node visibility_node setup_planner_node roughing_planner_node \
                finishing_planner_node verification_node controller_bridge_node simulated_controller_node cell_rviz.py; do
      timeout 20 rosrun --prefix echo art2part "$node" </dev/null >"$tmp/run" 2>&1 || fail "rosrun art2part $node: $(cat "$tmp/run")"
      [ "$(wc -l <"$tmp/run")" = 1 ] || fail "rosrun art2part $node: $(cat "$tmp/run")"
    done
    if [ -x "$expected/scripts/stage_env.sh" ]; then  # cell.launch's env loader for the stage host (devel space)
      [ "$("$expected/scripts/stage_env.sh" rospack find art2part)" = "$expected" ] || fail "scripts/stage_env.sh"
    fi
    cd "$tmp" && python3 -c "import art2part.srv, art2part.msg" || fail "python3 cannot import art2part.srv, art2part.msg"

    # Every parameter comes from config/cell.yaml, the machine file from the machine argument.
    timeout 60 roslaunch --dump-params art2part cell.launch machine:=trunnion_ac "${cell_args[@]}" >"$tmp/params" \
      || fail "roslaunch --dump-params art2part cell.launch"
    python3 - "$tmp/params" "$expected" <<'PY' || fail "cell.launch parameters (above)"
import sys, yaml
params, pkg = yaml.safe_load(open(sys.argv[1])), sys.argv[2]
want = {'/part_server/frame_id': 'part', '/roughing_planner/tools': pkg + '/config/tools.yaml',
        '/controller_bridge/machine': pkg + '/config/machines/trunnion_ac.yaml',
        '/simulated_controller/machine': pkg + '/config/machines/trunnion_ac.yaml',
        '/part_server/part_file': pkg + '/examples/nist_ctc_01_asme1_rd.stp'}
bad = {k: params.get(k) for k, v in want.items() if params.get(k) != v}
if bad: sys.exit('cell.launch: %s' % bad)
if '<robot' not in params.get('/robot_description', ''): sys.exit('cell.launch: no robot_description')
PY
    # The heavy stage nodes go to stage_host; the part server and the controllers stay.
    python3 - "${cell_args[@]}" <<'PY' || fail "cell.launch machine tags (above)"
import sys, roslaunch.config, roslaunch.rlutil
launch = roslaunch.rlutil.resolve_launch_arguments(['art2part', 'cell.launch'])[0]
config = roslaunch.config.load_config_default([(launch, sys.argv[1:] + ['stage_host:=10.1.2.3'])], None)
machines = config.machines
where = {n.name: machines[n.machine_name].address if n.machine_name in machines else 'localhost'
         for n in config.nodes}
remote = {'visibility', 'setup_planner', 'roughing_planner', 'finishing_planner', 'verification'}
for name, address in where.items():
    if (address == '10.1.2.3') != (name in remote): sys.exit('cell.launch: %s on %s' % (name, address))
if not remote <= set(where): sys.exit('cell.launch lacks %s' % (remote - set(where)))
PY
  ) || exit 1
}

check_space "$devel/setup.bash" "$(dirname "$devel")/src/art2part"
echo "launch_by_name: devel space ok"

# The install space: `catkin_make install` (here: cmake --install on what is already built).
cmake --install "$build" >"$tmp/install.log" 2>&1 || { tail -20 "$tmp/install.log"; fail "cmake --install $build"; }
links=$(find "$install/share/art2part" "$install/lib/art2part" -type l)
[ -z "$links" ] || fail "the install space holds links into the source tree: $links"
check_space "$install/setup.bash" "$install/share/art2part"
echo "launch_by_name: install space ok"
