#!/usr/bin/python3
"""The [DISPLAY] program of test/linuxcnc/xyzac-trt-test.ini: drives LinuxCNC's simulated xyzac-trt machine through the
`linuxcnc` Python module (Debian's /usr/bin/python3) and checks our post against it. Started by `linuxcnc -r INI`
(run_sim_test.sh) with `-ini FILE`; reads the job from $A2P_JOB_DIR (program.ngc, tool.tbl, toolpaths.csv,
trajectory.csv: what `art2part post --mode 5axis` wrote) and writes its verdict to $A2P_RESULT (JSON).

Phase 1, identity kinematics (switchkins type 0: M429, the start-up mode; what our programs are written for):
  home, run program.ngc to its end in AUTO with our tool table (feed override $A2P_FEED_OVERRIDE, default 4), while
  HAL's sampler records joint.N.pos-fb and joint.N.pos-cmd every servo cycle (1 ms: all joints of one cycle; polling
  linuxcnc.stat instead once gave a sample 0.0012 mm off the path in X alone, as if its joints came from two
  cycles). The expected path is the
  post's joint polyline: the position before the program, then the joints after every motion line of program.ngc
  (X Y Z words + the G43 tool length in Z, G53 Z as is, A C in degrees): our inverse kinematics of every toolpath
  point and of the subdivision points between them.
  * every sample must lie on that polyline, reached in order (each sample on the segment of the one before or a later
    one), within 1e-3 mm over X Y Z and 1e-3 deg over A C. The joints mix mm and deg: the nearest point of a segment
    is taken in the 5-D space with 1 deg counted as 1 mm (the two tolerances are alike), and there the linear and the
    rotary parts of the distance are measured apart (`polyline_deviation`);
  * the final joints must equal the program's last waypoint and trajectory.csv's last row, within 1e-3.
  A program that blends (G64 P, what the post wrote for 5-axis before it wrote G61) is checked this way on a copy
  with G61 for G64, then run as written at 100 % feed, where the blends are measured and only a sanity bound held.
Phase 2, xyzac-trt-kins (switchkins type 1: M428, LinuxCNC's own tool-centre-point kinematics):
  for every toolpath point, in order, move (MDI G1, G43 active) to the tip in the table frame (toolpaths.csv x y z:
  the default fixture puts the part frame on the table frame) with the A and C of the program line our post made for
  it, and compare the joints LinuxCNC's inverse kinematics computes with that line's joints, within 1e-3 mm / 1e-3
  deg. The line is the first one from the previous point's on whose A, C give the point's tool axis by LinuxCNC's
  kinematics ((R_x(A) R_z(C))^T z = (sin C sin A, cos C sin A, cos A), trtfuncs.c) within 1e-3 deg, and among the
  lines with those same rotaries, the one whose joints LinuxCNC reproduces.
  The last toolpath point's check is "the final joints equal our IK of the last point" under LinuxCNC's kinematics.
"""
import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time

import linuxcnc

SERVO_PERIOD = 0.001  # s, [EMCMOT] SERVO_PERIOD of the INI
LINEAR_TOL = 1e-3   # mm
ROTARY_TOL = 1e-3   # deg
LOOSE_TOL = 0.25   # mm and deg: a sanity bound for a program that blends 5-axis corners (G64 P); measured: 0.074
NAMES = "XYZAC"
FEED_OVERRIDE = float(os.environ.get("A2P_FEED_OVERRIDE", "4"))
DRIVER_TIMEOUT = int(os.environ.get("A2P_DRIVER_TIMEOUT", "140"))


class Failure(Exception):
    pass


def log(text):
    print("sim_driver: " + text, flush=True)


# ---- the job files ---------------------------------------------------------------------------------------------------

def tool_lengths(job):
    """Tool number -> length offset (mm) of tool.tbl, each checked against its tool in tools.json (the length our
    inverse kinematics used: stickout + the holder's steps), so that the tool table cannot hide a wrong length."""
    with open(os.path.join(job, "tools.json")) as f:
        gauge = {t["id"]: t["stickout"] + sum(step[1] for step in t["holder"]) for t in json.load(f)}
    lengths = {}
    with open(os.path.join(job, "tool.tbl")) as f:
        for line in f:
            data, _, comment = line.partition(";")
            words = data.split()
            tool = next((w for w in words if w[0] in "Tt"), None)
            z = next((w for w in words if w[0] in "Zz"), None)
            if not tool:
                continue
            number, length = int(float(tool[1:])), float(z[1:]) if z else 0.0
            ident = comment.split()[0] if comment.split() else "?"
            if ident not in gauge or abs(gauge[ident] - length) > 1e-6:
                raise Failure("tool.tbl T%d (%s) has length %.6f mm, tools.json says %s" % (
                    number, ident, length, "%.6f mm" % gauge[ident] if ident in gauge else "no such tool"))
            lengths[number] = length
    return lengths


WORD = re.compile(r"([A-Z])\s*([-+]?[0-9]*\.?[0-9]+)")


G83_RAPID_DELTA = 0.010 * 25.4  # mm: rs274ngc's G83 comes back down to this above the depth reached


def cycle_moves(z_now, x, y, z, r, q, old_z_mode):
    """A canned drilling cycle (G81, or G83 when q > 0) as rs274ngc expands it (interp_cycles.cc), from program Z
    z_now: [(x, y, z, motion)] with motion 0 rapid, 1 feed. The retract is split at R when it passes it (a toolpath
    point lies there)."""
    moves = []
    old_z = z_now
    if z_now < r:
        moves.append((None, None, r, 0))
        z_now = r
    moves.append((x, y, z_now, 0))
    if z_now != r:
        moves.append((x, y, r, 0))
    if q > 0:
        d = r - q
        while d > z:
            moves += [(x, y, d, 1), (x, y, r, 0), (x, y, d + G83_RAPID_DELTA, 0)]
            d -= q
    moves.append((x, y, z, 1))
    clear = max(old_z, r) if old_z_mode else r
    if clear > r:
        moves.append((x, y, r, 0))
    moves.append((x, y, clear, 0))
    return moves


def program_waypoints(path, lengths, start):
    """The joints (mm, deg) after every motion line of program.ngc, from `start`; with the line numbers (N). A canned
    drilling cycle's line gives every move of the cycle (cycle_moves)."""
    joints = list(start)
    tool, length, motion, old_z_mode = 0, 0.0, None, True
    waypoints = []
    with open(path) as f:
        for raw in f:
            text = re.sub(r"\([^)]*\)", "", raw.split(";")[0]).upper()
            words = WORD.findall(text)
            if not words:
                continue
            number = next((v for k, v in words if k == "N"), "?")
            g = [float(v) for k, v in words if k == "G"]
            for k, v in words:
                if k == "T":
                    tool = int(float(v))
            if 43 in g:
                h = next((int(float(v)) for k, v in words if k == "H"), tool)
                length = lengths[h]
            if 49 in g:
                length = 0.0
            for code in g:
                if code in (0, 1, 81, 83):
                    motion = int(code)
                if code == 80:
                    motion = None
                if code in (98, 99):
                    old_z_mode = code == 98
            axis_words = {k: float(v) for k, v in words if k in NAMES}
            if not axis_words or 10 in g or 92 in g or 92.1 in g:
                continue
            if motion is None:
                raise Failure("program.ngc N%s: axis words without G0/G1" % number)
            if motion in (81, 83):
                value = dict((k, float(v)) for k, v in words)
                if "R" not in value or "Z" not in value or (motion == 83 and "Q" not in value):
                    raise Failure("program.ngc N%s: a canned cycle needs Z, R (and Q for G83)" % number)
                x, y = value.get("X", joints[0]), value.get("Y", joints[1])
                for mx, my, mz, kind in cycle_moves(joints[2] - length, x, y, value["Z"], value["R"],
                                                    value.get("Q", 0.0) if motion == 83 else 0.0, old_z_mode):
                    if mx is not None:
                        joints[0], joints[1] = mx, my
                    joints[2] = mz + length
                    waypoints.append((number, list(joints), kind))
                continue
            for k, v in axis_words.items():
                i = NAMES.index(k)
                if 53 in g:
                    joints[i] = v
                elif k == "Z":
                    joints[i] = v + length
                else:
                    joints[i] = v
            waypoints.append((number, list(joints), motion))
    return waypoints


def read_toolpath(path):
    rows = []
    with open(path) as f:
        for row in csv.DictReader(f):
            rows.append({
                "line": len(rows) + 2,
                "op": int(row["op"]),
                "tip": [float(row[k]) for k in "xyz"],
                "axis": [float(row[k]) for k in "ijk"],
            })
    return rows


def read_trajectory_end(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return [float(v) for v in rows[-1][1:]], float(rows[-1][0])


# ---- geometry ----------------------------------------------------------------------------------------------------------

def split_deviation(a, b):
    """Largest |difference| of the linear joints (mm) and of the rotary joints (deg)."""
    lin = max(abs(a[i] - b[i]) for i in range(3))
    rot = max(abs(a[i] - b[i]) for i in range(3, 5))
    return lin, rot


def polyline_deviation(p, a, b):
    """Distance from p to the segment a-b. The joints mix mm and deg: the nearest point is found in the 5-D space with
    1 deg counted as 1 mm (the two tolerances are both 1e-3, so this weighs them alike), and there the linear and the
    rotary parts are measured apart, as Euclidean distances: (mm over X Y Z, deg over A C)."""
    d = [b[i] - a[i] for i in range(5)]
    dd = sum(x * x for x in d)
    t = 0.0 if dd == 0 else max(0.0, min(1.0, sum((p[i] - a[i]) * d[i] for i in range(5)) / dd))
    q = [a[i] + t * d[i] for i in range(5)]
    lin = math.sqrt(sum((p[i] - q[i]) ** 2 for i in range(3)))
    rot = math.sqrt(sum((p[i] - q[i]) ** 2 for i in range(3, 5)))
    return lin, rot


def axis_of(a_deg, c_deg):
    """The tool axis in the table frame at A, C: (R_x(A) R_z(C))^T z, the rotation xyzac-trt-kins applies."""
    a, c = math.radians(a_deg), math.radians(c_deg)
    return (math.sin(c) * math.sin(a), math.cos(c) * math.sin(a), math.cos(a))


def angle_deg(u, v):
    cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return math.degrees(math.atan2(math.sqrt(sum(x * x for x in cross)), sum(x * y for x, y in zip(u, v))))


# ---- LinuxCNC ------------------------------------------------------------------------------------------------------------

class Machine:
    def __init__(self):
        self.s = linuxcnc.stat()
        self.c = linuxcnc.command()
        self.e = linuxcnc.error_channel()

    def poll(self):
        self.s.poll()
        while True:
            error = self.e.poll()
            if not error:
                break
            kind, text = error
            if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR):
                raise Failure("LinuxCNC error: " + text)
            log("message: " + text)
        return self.s

    def wait(self, condition, what, timeout=10.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if condition(self.poll()):
                return
            time.sleep(0.01)
        raise Failure("timed out after %.0f s waiting for %s" % (timeout, what))

    def start(self):
        end = time.monotonic() + 20
        while True:
            try:
                self.s.poll()
                break
            except linuxcnc.error:
                if time.monotonic() > end:
                    raise Failure("LinuxCNC task never answered")
                time.sleep(0.1)
        self.c.state(linuxcnc.STATE_ESTOP_RESET)
        self.wait(lambda s: s.task_state == linuxcnc.STATE_ESTOP_RESET, "estop reset")
        self.c.state(linuxcnc.STATE_ON)
        self.wait(lambda s: s.task_state == linuxcnc.STATE_ON, "machine on")
        self.c.mode(linuxcnc.MODE_MANUAL)
        self.c.wait_complete()
        self.c.home(-1)
        self.c.wait_complete()
        self.wait(lambda s: all(s.homed[:5]), "homing", 20)

    def mdi(self, text, timeout=20.0):
        if self.poll().task_mode != linuxcnc.MODE_MDI:
            self.c.mode(linuxcnc.MODE_MDI)
            self.c.wait_complete()
            self.wait(lambda s: s.task_mode == linuxcnc.MODE_MDI, "MDI mode")
        self.c.mdi(text)
        self.c.wait_complete(timeout)
        self.wait(lambda s: s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.inpos, "MDI '%s'" % text,
                  timeout)

    def settled_joints(self):
        """Joints after a motion has ended: fed back and commanded agree and two polls in a row agree."""
        last = None
        end = time.monotonic() + 2
        while time.monotonic() < end:
            s = self.poll()
            actual, commanded = list(s.joint_actual_position[:5]), list(s.joint_position[:5])
            if last == actual and max(abs(x - y) for x, y in zip(actual, commanded)) < 1e-9:
                return actual
            last = actual
            time.sleep(0.01)
        return last

    def kinematics(self, code, kinstype):
        """M429 (identity, type 0) or M428 (xyzac-trt-kins, type 1), checked on the HAL pin."""
        self.mdi(code)
        now = halcmd("getp", "motion.switchkins-type")
        if abs(float(now) - kinstype) > 1e-9:
            raise Failure("%s left motion.switchkins-type at %s, expected %d" % (code, now, kinstype))


def halcmd(*args):
    done = subprocess.run(["halcmd"] + list(args), capture_output=True, text=True, timeout=10)
    if done.returncode != 0:
        raise Failure("halcmd %s: %s" % (" ".join(args), done.stderr.strip()))
    return done.stdout.strip()


class Sampler:
    """The joints of every servo cycle (HAL sampler.0, see the INI), from now until stop(), through halsampler."""

    def __init__(self, path):
        self.path = path
        halcmd("setp", "sampler.0.enable", "0")
        self.file = open(path, "w")
        # line-buffered, so that nothing is left in halsampler's buffer when it is stopped
        self.process = subprocess.Popen(["stdbuf", "-oL", "halsampler", "-t"], stdout=self.file,
                                        stderr=subprocess.STDOUT)
        time.sleep(0.2)
        halcmd("setp", "sampler.0.enable", "1")

    def stop(self):
        """(time s, joints fed back, joints commanded, program line) of every cycle; Failure when cycles are missing."""
        try:
            halcmd("setp", "sampler.0.enable", "0")
            # drained: the FIFO empty and the file no longer growing
            end, size = time.monotonic() + 10, -1
            while time.monotonic() < end:
                time.sleep(0.2)
                grown = os.path.getsize(self.path)
                if grown == size and int(halcmd("getp", "sampler.0.curr-depth")) == 0:
                    break
                size = grown
            overruns = int(halcmd("getp", "sampler.0.overruns"))
        finally:
            self.process.terminate()
            try:
                self.process.wait(5)
            except subprocess.TimeoutExpired:
                self.process.kill()
            self.file.close()
        samples = []
        first = None
        with open(self.path) as f:
            for number, line in enumerate(f):
                words = line.split()
                if number == 0 and words == ["overrun"]:
                    continue  # the sample counter runs on from the last program: halsampler notes the jump
                if len(words) != 12:
                    raise Failure("halsampler: '%s' in %s (cycles lost)" % (line.strip(), self.path))
                tag = int(words[0])
                first = tag if first is None else first
                if tag != first + len(samples):
                    raise Failure("halsampler: sample %d follows %d: cycles lost" % (tag, first + len(samples) - 1))
                values = [float(w) for w in words[1:11]]
                samples.append(((tag - first) * SERVO_PERIOD, values[:5], values[5:], int(words[11])))
        if overruns:
            raise Failure("sampler: %d overruns (cycles lost)" % overruns)
        return samples


def follow(samples, column, polyline, lin_tol, rot_tol):
    """Walks the samples along the polyline in order: each sample is matched to the first segment, from the previous
    sample's on, within (lin_tol, rot_tol), then to the nearest of that one and the next few (a blend spans a corner).
    Returns the number of distinct samples, the worst (mm, deg) on feed segments and on rapid segments; raises Failure
    for a sample off the path."""
    segment, previous, distinct = 0, None, 0
    worst = {1: [0.0, 0.0], 0: [0.0, 0.0]}
    for sample in samples:
        p = sample[column]
        if p == previous:
            continue  # the status had not changed since the last poll
        previous = p
        distinct += 1
        found = None
        for k in range(segment, len(polyline) - 1):
            lin, rot = polyline_deviation(p, polyline[k][1], polyline[k + 1][1])
            if lin <= lin_tol and rot <= rot_tol:
                found = (k, lin, rot)
                break
        if found is None:
            (lin, rot), k = min(((polyline_deviation(p, polyline[k][1], polyline[k + 1][1]), k)
                                 for k in range(len(polyline) - 1)), key=lambda x: max(x[0]))
            raise Failure(
                "joints at t = %.3f s (line %d) %s are off the post's path beyond segment N%s -> N%s: nearest segment "
                "N%s -> N%s at %.6f mm / %.6f deg (allowed %g mm / %g deg)" % (
                    sample[0], sample[3], " ".join("%.4f" % v for v in p), polyline[segment][0],
                    polyline[segment + 1][0], polyline[k][0], polyline[k + 1][0], lin, rot, lin_tol, rot_tol))
        for k in range(found[0] + 1, min(found[0] + 4, len(polyline) - 1)):
            lin, rot = polyline_deviation(p, polyline[k][1], polyline[k + 1][1])
            if max(lin, rot) < max(found[1], found[2]):
                found = (k, lin, rot)
        segment = found[0]
        kind = 1 if polyline[segment + 1][2] == 1 else 0
        worst[kind][0] = max(worst[kind][0], found[1])
        worst[kind][1] = max(worst[kind][1], found[2])
    return distinct, worst[1], worst[0]


def run_program(machine, job, program, label, lin_tol, rot_tol, feed_override, result):
    """Runs `program` (identity kinematics, from where the machine is) to its end, sampling the joints; checks the
    samples against the post's joint polyline and the final joints against its last waypoint and trajectory.csv."""
    lengths = tool_lengths(job)
    machine.kinematics("M429", 0)  # identity kinematics: joints = axes
    start = machine.settled_joints()
    waypoints = program_waypoints(program, lengths, start)
    polyline = [("start", start, 0)] + waypoints

    c = machine.c
    c.mode(linuxcnc.MODE_AUTO)
    c.wait_complete()
    c.program_open(program)
    c.wait_complete()
    c.feedrate(feed_override)
    sampler = Sampler(os.path.splitext(program)[0] + "_samples.txt")
    began = time.monotonic()
    c.auto(linuxcnc.AUTO_RUN, 0)
    started = False
    try:
        while True:
            s = machine.poll()
            now = time.monotonic() - began
            running = s.interp_state != linuxcnc.INTERP_IDLE or s.queue > 0 or not s.inpos
            started = started or running
            if started and not running:
                break
            if not started and now > 5:
                raise Failure("%s did not start" % label)
            if now > DRIVER_TIMEOUT / 2:
                raise Failure("%s still running after %.0f s (line %d)" % (label, now, s.motion_line))
            if s.task_state != linuxcnc.STATE_ON:
                raise Failure("the machine went off (state %d) at line %d of %s" % (s.task_state, s.motion_line,
                                                                                      label))
            time.sleep(0.01)
        run_seconds = time.monotonic() - began
        final = machine.settled_joints()
    finally:
        samples = sampler.stop()

    distinct, feed, rapid = follow(samples, 1, polyline, lin_tol, rot_tol)
    _, feed_cmd, rapid_cmd = follow(samples, 2, polyline, lin_tol, rot_tol)
    expected = polyline[-1][1]
    trajectory_end, trajectory_seconds = read_trajectory_end(os.path.join(job, "trajectory.csv"))
    lin, rot = split_deviation(final, expected)
    lin_t, rot_t = split_deviation(final, trajectory_end)
    result[label] = {
        "motion_lines": len(waypoints), "samples": len(samples), "distinct_samples": distinct,
        "run_seconds": round(run_seconds, 3), "feed_override": feed_override,
        "trajectory_csv_seconds": trajectory_seconds,
        "max_deviation_feed_mm": feed[0], "max_deviation_feed_deg": feed[1],
        "max_deviation_rapid_mm": rapid[0], "max_deviation_rapid_deg": rapid[1],
        "commanded_max_deviation_feed_mm": feed_cmd[0], "commanded_max_deviation_feed_deg": feed_cmd[1],
        "commanded_max_deviation_rapid_mm": rapid_cmd[0], "commanded_max_deviation_rapid_deg": rapid_cmd[1],
        "final_joints": final, "final_expected": expected,
        "final_deviation_mm": lin, "final_deviation_deg": rot,
        "final_vs_trajectory_csv_mm": lin_t, "final_vs_trajectory_csv_deg": rot_t,
    }
    log("%s: %d motion lines ran in %.2f s (feed override %g; trajectory.csv: %.2f s at 100%%), %d joint samples "
        "(%d distinct); max distance from the post's joint path: feed moves %.6f mm / %.6f deg, rapids %.6f mm / "
        "%.6f deg (commanded joints: %.6f mm / %.6f deg, %.6f mm / %.6f deg)" % (
            label, len(waypoints), run_seconds, feed_override, trajectory_seconds, len(samples), distinct, feed[0],
            feed[1], rapid[0], rapid[1], feed_cmd[0], feed_cmd[1], rapid_cmd[0], rapid_cmd[1]))
    log("%s: final joints %s; program's last waypoint %s: %.6f mm / %.6f deg; trajectory.csv's last row: %.6f mm / "
        "%.6f deg" % (label, " ".join("%.4f" % v for v in final), " ".join("%.4f" % v for v in expected), lin, rot,
                      lin_t, rot_t))
    if distinct < 50:
        raise Failure("%s: only %d distinct joint samples during the run" % (label, distinct))
    if lin > LINEAR_TOL or rot > ROTARY_TOL:
        raise Failure("%s: final joints differ from the program's last waypoint by %.6f mm / %.6f deg" % (
            label, lin, rot))
    if lin_t > LINEAR_TOL or rot_t > ROTARY_TOL:
        raise Failure("%s: final joints differ from trajectory.csv's last row by %.6f mm / %.6f deg" % (
            label, lin_t, rot_t))
    return waypoints, lengths


def phase_tcp(machine, job, waypoints, lengths, result):
    rows = read_toolpath(os.path.join(job, "toolpaths.csv"))
    tool_length = lengths[1]
    machine.mdi("G90 G94 G40 G17 G54")
    machine.mdi("T1 M6")
    machine.mdi("G43 H1")
    s = machine.poll()
    if abs(s.tool_offset[2] - tool_length) > 1e-9:
        raise Failure("tool offset %.6f after G43 H1, expected %.6f" % (s.tool_offset[2], tool_length))

    def lines_for(r, q):
        """The program lines from q on whose A, C give point r's tool axis (by xyzac-trt's rotation), first ones first."""
        for k in range(q, len(waypoints)):
            if angle_deg(axis_of(waypoints[k][1][3], waypoints[k][1][4]), rows[r]["axis"]) <= 1e-3:
                yield k

    def reproduced(joints, q):
        """Among the lines from q on with q's rotaries, the one nearest the joints: (line, mm, deg)."""
        best = None
        k = q
        while k < len(waypoints) and waypoints[k][1][3:] == waypoints[q][1][3:]:
            lin, rot = split_deviation(joints, waypoints[k][1])
            if best is None or max(lin, rot) < max(best[1], best[2]):
                best = (k, lin, rot)
            k += 1
        return best

    # start on the first point's line, moving there in joint space (identity kinematics, a straight joint move)
    q = next(lines_for(0, 0), None)
    if q is None:
        raise Failure("toolpaths.csv line 2: no program line has A C giving its tool axis %s" % rows[0]["axis"])
    j = waypoints[q][1]
    machine.mdi("G0 X%.6f Y%.6f Z%.6f A%.6f C%.6f" % (j[0], j[1], j[2] - tool_length, j[3], j[4]))
    machine.kinematics("M428", 1)  # xyzac-trt-kins
    began = time.monotonic()
    worst_lin = worst_rot = 0.0
    for r, row in enumerate(rows):
        # the tip with the rotaries of the first line that gives the point's axis; should LinuxCNC's joints match no
        # line with those rotaries (a subdivision point's axis within 1e-3 deg of the point's), the next such line's
        tried, found, nearest = [], None, None
        for k in lines_for(r, q):
            a, c = waypoints[k][1][3], waypoints[k][1][4]
            if (a, c) in tried:
                continue
            if len(tried) == 3:
                break
            tried.append((a, c))
            machine.mdi("G1 X%.6f Y%.6f Z%.6f A%.6f C%.6f F6000" % (tuple(row["tip"]) + (a, c)))
            joints = machine.settled_joints()
            line, lin, rot = reproduced(joints, k)
            if nearest is None or max(lin, rot) < max(nearest[2], nearest[3]):
                nearest = (joints, line, lin, rot, a, c)
            if lin <= LINEAR_TOL and rot <= ROTARY_TOL:
                found = (joints, line, lin, rot)
                break
        if found is None:
            if nearest is None:
                raise Failure("toolpaths.csv line %d (op %d): no program line from N%s on has A C giving its tool "
                              "axis %s" % (row["line"], row["op"], waypoints[q][0], row["axis"]))
            joints, line, lin, rot, a, c = nearest
            raise Failure(
                "toolpaths.csv line %d (op %d): LinuxCNC's xyzac-trt-kins puts the joints at %s for tip %s, A %.4f, "
                "C %.4f; our program line N%s has %s: %.6f mm / %.6f deg apart" % (
                    row["line"], row["op"], " ".join("%.4f" % v for v in joints), row["tip"], a, c,
                    waypoints[line][0], " ".join("%.4f" % v for v in waypoints[line][1]), lin, rot))
        joints, q, lin, rot = found
        worst_lin, worst_rot = max(worst_lin, lin), max(worst_rot, rot)
    k = q
    log("last toolpath point (toolpaths.csv line %d) under xyzac-trt-kins: joints %s, our IK (program line N%s) %s: "
        "%.6f mm / %.6f deg" % (row["line"], " ".join("%.4f" % v for v in joints), waypoints[k][0],
                                " ".join("%.4f" % v for v in waypoints[k][1]), lin, rot))
    result["tcp"] = {"points": len(rows), "max_deviation_mm": worst_lin, "max_deviation_deg": worst_rot,
                     "last_point": {"toolpath_line": row["line"], "program_line": waypoints[k][0], "joints": joints,
                                    "expected": waypoints[k][1], "deviation_mm": lin, "deviation_deg": rot}}
    log("xyzac-trt-kins: %d toolpath points in %.1f s, LinuxCNC's inverse kinematics vs ours: max %.6f mm / %.6f deg"
        % (len(rows), time.monotonic() - began, worst_lin, worst_rot))
    machine.kinematics("M429", 0)


def main():
    job = os.environ["A2P_JOB_DIR"]
    result_path = os.environ["A2P_RESULT"]
    result = {"ok": False}

    def expired(signum, frame):
        raise Failure("driver time limit %d s reached" % DRIVER_TIMEOUT)

    signal.signal(signal.SIGALRM, expired)
    signal.alarm(DRIVER_TIMEOUT)
    machine = None
    try:
        machine = Machine()
        machine.start()
        log("machine on and homed")
        program = os.path.join(job, "program.ngc")
        with open(program) as f:
            text = f.read()
        if re.search(r"\bG61\b", text) and not re.search(r"\bG64\b", text):
            # the post's 5-axis programs: exact path, checked as written
            waypoints, lengths = run_program(machine, job, program, "program.ngc (G61)", LINEAR_TOL, ROTARY_TOL,
                                             FEED_OVERRIDE, result)
            phase_tcp(machine, job, waypoints, lengths, result)
        elif re.search(r"\bG64 P[0-9.]+", text):
            # a post that blends 5-axis corners (G64 P, art2part before G61): the strict checks on an exact-path copy,
            # then the program as written, its blending measured (LOOSE_TOL is a sanity bound, not the tolerance)
            exact_program = os.path.join(job, "program_exact_path.ngc")
            with open(exact_program, "w") as f:
                f.write(re.sub(r"G64 P[0-9.]+", "G61", text))
            waypoints, lengths = run_program(machine, job, exact_program, "program.ngc with G61 for G64",
                                             LINEAR_TOL, ROTARY_TOL, FEED_OVERRIDE, result)
            phase_tcp(machine, job, waypoints, lengths, result)
            run_program(machine, job, program, "program.ngc as written (G64 P, blended)", LOOSE_TOL, LOOSE_TOL, 1.0,
                        result)
        else:
            raise Failure("program.ngc sets neither G61 nor G64 P")
        result["ok"] = True
    except Failure as failure:
        result["error"] = str(failure)
        log("FAIL: " + str(failure))
    except Exception as error:  # a bug here or a LinuxCNC exception: report, never hang
        result["error"] = "%s: %s" % (type(error).__name__, error)
        log("FAIL: " + result["error"])
    finally:
        signal.alarm(0)
        with open(result_path, "w") as f:
            json.dump(result, f, indent=2)
        if machine is not None:
            try:
                machine.c.abort()
                machine.c.state(linuxcnc.STATE_ESTOP)
            except Exception:
                pass
    return 0 if result["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
