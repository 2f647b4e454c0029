#!/usr/bin/python3
"""Writes a hand-made continuous 5-axis job for the trunnion_ac machine: DIR/toolpaths.csv and DIR/tools.json.

The same motions as test/test_post.cpp's fiveAxisPath(), shortened so that the simulated machine runs it in seconds:
  op 0  a circle of radius 15 mm at z = 10 with the tool axis leaning 30 deg outwards: C turns a whole turn and
        crosses +-180 deg, every joint moves at once (G93 inverse time);
  op 1  a pass whose axis sweeps 0.6 deg past the C axis (C swings half a turn);
  op 2  the same straight through the singularity (C held);
  op 3  a 3-axis-like stretch (fixed tilted axis: X Y Z feed moves in G94 after the rotaries are positioned).
With --drill, a 3+2 drilling job instead (holes.h's drillingPath layout): one setup whose axis leans 20 deg (the
rotaries positioned once), a 6.8 mm drill down a hole 12 mm from its R plane (G81) and one 27 mm (G83, pecks of
10 mm), each from the clearance height down to 2 mm over its mouth, to its depth, and back up (G98).
Usage: make_toolpath.py DIR [--drill]
"""
import json
import math
import os
import sys

TOOL = "ball6"


def row(op, move, tip, axis):
    n = math.sqrt(sum(c * c for c in axis))
    axis = [c / n for c in axis]
    return "%d,0,%s,%s,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f" % (op, TOOL, move, *tip, *axis)


def main(out):
    rows = []
    lean = math.radians(30)
    # op 0: 36 steps of 10 deg
    for k in range(37):
        theta = math.radians(10 * k)
        axis = (math.sin(lean) * math.cos(theta), math.sin(lean) * math.sin(theta), math.cos(lean))
        tip = (15 * math.cos(theta), 15 * math.sin(theta), 10.0)
        if k == 0:
            rows.append(row(0, "rapid", [t + 10 * a for t, a in zip(tip, axis)], axis))
        rows.append(row(0, "feed", tip, axis))
    last_tip, last_axis = tip, axis
    rows.append(row(0, "rapid", [t + 10 * a for t, a in zip(last_tip, last_axis)], last_axis))
    # ops 1, 2: past and through the singularity
    for op, offset in ((1, 0.01), (2, 0.0)):
        for k in range(13):
            psi = math.radians(30 - 5 * k)
            axis = (offset, math.sin(psi), math.cos(psi))
            tip = (-10 + k * 20.0 / 12, 2.0 if offset > 0 else -2.0, 15.0)
            if k == 0:
                rows.append(row(op, "rapid", [t + 10 * a for t, a in zip(tip, axis)], axis))
            rows.append(row(op, "feed", tip, axis))
        n = math.sqrt(sum(c * c for c in axis))
        axis = [c / n for c in axis]
        rows.append(row(op, "rapid", [t + 10 * a for t, a in zip(tip, axis)], axis))
    # op 3: a square at a fixed tilted axis
    axis = (0.0, -math.sin(math.radians(20)), math.cos(math.radians(20)))
    corners = [(-8, -8), (8, -8), (8, 8), (-8, 8), (-8, -8)]
    for k, (x, y) in enumerate(corners):
        tip = (float(x), float(y), 5.0)
        if k == 0:
            rows.append(row(3, "rapid", [t + 10 * a for t, a in zip(tip, axis)], axis))
        rows.append(row(3, "feed", tip, axis))
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "toolpaths.csv"), "w") as f:
        f.write("op,setup,tool,move,x,y,z,i,j,k\n")
        f.write("\n".join(rows) + "\n")
    tools = [{
        "id": TOOL, "type": "ball", "diameter": 6, "corner_radius": 3, "flute_length": 15, "shank_diameter": 6,
        "stickout": 30, "holder": [[20, 30]], "spindle_rpm": 8000, "feed_mm_min": 600, "plunge_mm_min": 200,
    }]
    with open(os.path.join(out, "tools.json"), "w") as f:
        json.dump(tools, f, indent=2)
        f.write("\n")


def drilling(out):
    tool = "drill6.8"
    lean = math.radians(20)
    axis = (0.0, -math.sin(lean), math.cos(lean))
    dot = lambda a, b: sum(x * y for x, y in zip(a, b))
    along = lambda p, t: [c + t * a for c, a in zip(p, axis)]
    holes = [((-8.0, -4.0, 5.0), 10.0), ((8.0, 4.0, 5.0), 25.0)]
    level = max(dot(m, axis) for m, _ in holes) + 10
    rows = []
    for mouth, depth in holes:
        above, r_plane = along(mouth, level - dot(mouth, axis)), along(mouth, 2)
        for move, tip in (("rapid", above), ("rapid", r_plane), ("feed", along(mouth, -depth)), ("rapid", r_plane),
                          ("rapid", above)):
            rows.append("0,0,%s,%s,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f" % (tool, move, *tip, *axis))
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "toolpaths.csv"), "w") as f:
        f.write("op,setup,tool,move,x,y,z,i,j,k\n")
        f.write("\n".join(rows) + "\n")
    tools = [{
        "id": tool, "type": "drill", "diameter": 6.8, "corner_radius": 0, "point_angle_deg": 118, "flute_length": 28,
        "shank_diameter": 6.8, "stickout": 30, "holder": [[20, 30]], "spindle_rpm": 8000, "feed_mm_min": 500,
        "plunge_mm_min": 500, "max_stepdown": 10,
    }]
    with open(os.path.join(out, "tools.json"), "w") as f:
        json.dump(tools, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[2] == "--drill":
        drilling(sys.argv[1])
    elif len(sys.argv) == 2:
        main(sys.argv[1])
    else:
        sys.exit("usage: make_toolpath.py DIR [--drill]")
