#!/bin/bash
# Integration test: a 5-axis program from our post, run on LinuxCNC 2.9's simulated xyzac-trt machine, headless.
#
#   test/linuxcnc/run_sim_test.sh [ART2PART_BINARY [JOB]]  (default: catkin_ws/devel/lib/art2part/art2part, 5axis)
#
# 1. make_toolpath.py writes a hand-made job (toolpaths.csv, tools.json): JOB 5axis, a continuous 5-axis job; JOB
#    drill, a 3+2 drilling job (G81 and G83 canned cycles at a tilted axis);
# 2. `art2part post --machine config/machines/trunnion_ac.yaml --mode 5axis` (drill: --mode 3+2) writes program.ngc,
#    tool.tbl, trajectory.csv;
# 3. LinuxCNC starts headless (`linuxcnc -r`, xyzac-trt-test.ini: the sample sim's kinematics and travel, no GUI) with
#    sim_driver.py as its display program, which homes, runs program.ngc with our tool table under identity kinematics
#    while sampling the joints, then checks every toolpath point under LinuxCNC's xyzac-trt-kins (see sim_driver.py);
# 4. pass when every joint sample lies on the post's joint path and the final joints and LinuxCNC's inverse kinematics
#    of every toolpath point equal ours, within 1e-3 mm and 1e-3 deg.
# Exit status: 0 pass, 1 fail (the reason on the last lines), 77 skipped (no LinuxCNC, not root, another LinuxCNC
# running). Everything runs in a mktemp -d folder, removed at the end (kept when A2P_KEEP=1); LinuxCNC is
# shut down and realtime stopped whatever happens; once LinuxCNC is free (at most 90 s of waiting for another run), the
# test is limited to A2P_TIME_LIMIT seconds (default 170). Takes about 45 s (90 s with a post that writes G64 for 5-axis).
set -u

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$HERE/../.." && pwd)
ART2PART=${1:-$REPO/catkin_ws/devel/lib/art2part/art2part}
JOB_KIND=${2:-5axis}
case $JOB_KIND in
  5axis) MAKE_ARGS=(); POST_MODE=5axis;;
  drill) MAKE_ARGS=(--drill); POST_MODE=3+2;;
  *) echo "linuxcnc_sim: FAIL: unknown job '$JOB_KIND' (5axis or drill)"; exit 1;;
esac
TIME_LIMIT=${A2P_TIME_LIMIT:-170}
PY=/usr/bin/python3            # Debian's python3: the one with the `linuxcnc` module
SKIP=77

say() { echo "linuxcnc_sim: $*"; }
elapsed() { echo "$(date +%s.%N) $BEGAN" | awk '{printf "%.1f", $1 - $2}'; }

# ---- what the test needs ------------------------------------------------------------------------------------------
if ! command -v linuxcnc >/dev/null || ! command -v halcmd >/dev/null; then
  say "SKIP: LinuxCNC is not installed (apt-get install --no-install-recommends linuxcnc-uspace)"; exit $SKIP
fi
if ! "$PY" -c "import linuxcnc" 2>/dev/null; then
  say "SKIP: $PY has no linuxcnc module"; exit $SKIP
fi
if [ "$(id -u)" != 0 ]; then
  say "SKIP: this test starts the simulated machine as root (RTAPI_UID=65534); run it as root"; exit $SKIP
fi
if [ ! -x "$ART2PART" ]; then
  say "FAIL: no art2part binary at $ART2PART"; exit 1
fi

# ---- one LinuxCNC per machine: wait for ours (flock), never clean up someone else's ----------------------------------
exec 9>/tmp/art2part-linuxcnc.flock
if ! flock -w 60 9; then
  say "SKIP: another run of this test held the LinuxCNC lock for 60 s"; exit $SKIP
fi
for i in $(seq 30); do
  if ! pgrep -x milltask >/dev/null && ! pgrep -x linuxcncsvr >/dev/null && ! pgrep -x rtapi_app >/dev/null; then
    break
  fi
  if [ "$i" = 30 ]; then
    say "SKIP: another LinuxCNC (milltask / linuxcncsvr / rtapi_app) is running on this machine"; exit $SKIP
  fi
  sleep 1
done
if [ -f /tmp/linuxcnc.lock ]; then
  say "note: removing a stale /tmp/linuxcnc.lock (no LinuxCNC process is running)"
  rm -f /tmp/linuxcnc.lock
fi
BEGAN=$(date +%s.%N)   # the time limit counts from here

# ---- the work folder and the clean-up ------------------------------------------------------------------------------
WORK=$(mktemp -d /tmp/art2part-linuxcnc-sim.XXXXXX)
chmod 755 "$WORK"
mkdir -m 1777 "$WORK/rtapi"
JOB=$WORK/job
SIM=$WORK/sim
LCNC_PID=
STATUS=1

export RTAPI_UID=65534 RTAPI_FIFO_PATH=$WORK/rtapi/rtapi_fifo HOME=$WORK
unset DISPLAY WAYLAND_DISPLAY

cleanup() {
  trap - EXIT INT TERM
  if [ -n "$LCNC_PID" ] && kill -0 "$LCNC_PID" 2>/dev/null; then
    say "stopping LinuxCNC (pid $LCNC_PID)"
    kill -TERM "$LCNC_PID" 2>/dev/null          # its trap runs LinuxCNC's own Cleanup
    for i in $(seq 30); do kill -0 "$LCNC_PID" 2>/dev/null || break; sleep 1; done
    kill -KILL -- "-$LCNC_PID" 2>/dev/null      # what is left of its process group (setsid below)
  fi
  if [ -n "$LCNC_PID" ]; then
    # whatever LinuxCNC's Cleanup could not do: realtime (rtapi_app) and its lock file
    if pgrep -x rtapi_app >/dev/null || halcmd list comp >/dev/null 2>&1; then
      timeout 20 /usr/lib/linuxcnc/realtime stop >/dev/null 2>&1 || true
    fi
    rm -f /tmp/linuxcnc.lock
  fi
  if [ "${A2P_KEEP:-0}" = 1 ]; then
    say "kept $WORK"
  else
    rm -rf "$WORK"
  fi
  flock -u 9
  exit "$STATUS"
}
trap cleanup EXIT
trap 'say "interrupted"; STATUS=1; exit 1' INT TERM

# ---- the job and the post ------------------------------------------------------------------------------------------
"$PY" "$HERE/make_toolpath.py" "$JOB" "${MAKE_ARGS[@]}" || { say "FAIL: make_toolpath.py"; exit 1; }
if ! "$ART2PART" post "$JOB" --machine "$REPO/config/machines/trunnion_ac.yaml" --mode "$POST_MODE" >"$WORK/post.txt" 2>&1
then
  cat "$WORK/post.txt"; say "FAIL: art2part post"; exit 1
fi
sed -n 1p "$WORK/post.txt"

# ---- the simulated machine -----------------------------------------------------------------------------------------
mkdir -p "$SIM"
cp -r "$HERE/remap_subs" "$SIM/"
cp "$JOB/tool.tbl" "$SIM/tool.tbl"        # our tool table is the controller's
sed -e "s|@DRIVER@|$HERE/sim_driver.py|" "$HERE/xyzac-trt-test.ini" >"$SIM/xyzac-trt-test.ini"
export A2P_JOB_DIR=$JOB A2P_RESULT=$WORK/result.json
LIMIT=$(awk -v t="$TIME_LIMIT" -v e="$(elapsed)" 'BEGIN {print int(t - e - 35)}')
if [ "$LIMIT" -lt 30 ]; then say "FAIL: no time left for LinuxCNC (A2P_TIME_LIMIT $TIME_LIMIT s)"; exit 1; fi
export A2P_DRIVER_TIMEOUT=$((LIMIT - 15))

say "starting LinuxCNC headless ($SIM/xyzac-trt-test.ini), at most $LIMIT s"
setsid timeout -k 10 "$LIMIT" linuxcnc -r "$SIM/xyzac-trt-test.ini" </dev/null >"$WORK/linuxcnc.log" 2>&1 &
LCNC_PID=$!
wait "$LCNC_PID"
CODE=$?
grep "^sim_driver:" "$WORK/linuxcnc.log"
if [ "$CODE" = 124 ] || [ "$CODE" = 137 ]; then
  say "LinuxCNC's output:"; grep -v "^sim_driver:" "$WORK/linuxcnc.log" | tail -n 25
  say "FAIL: the LinuxCNC run hit its time limit ($LIMIT s of A2P_TIME_LIMIT $TIME_LIMIT s) and was stopped"
  exit 1
fi

if [ ! -s "$WORK/result.json" ]; then
  say "LinuxCNC's output:"; grep -v "^sim_driver:" "$WORK/linuxcnc.log" | tail -n 40
  say "FAIL: the driver wrote no result (LinuxCNC did not start, or the driver crashed) after $(elapsed) s"
  exit 1
fi
if "$PY" -c "import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))['ok'] else 1)" "$WORK/result.json"; then
  STATUS=0
  say "PASS in $(elapsed) s"
else
  grep -v "^sim_driver:" "$WORK/linuxcnc.log" | tail -n 25
  say "FAIL: $("$PY" -c "import json, sys; print(json.load(open(sys.argv[1])).get('error'))" "$WORK/result.json")"
  say "(after $(elapsed) s)"
fi
exit "$STATUS"
