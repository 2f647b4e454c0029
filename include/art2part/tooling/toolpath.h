// Toolpaths: cutter-location points in the part frame, the `toolpaths.csv` contract of architecture.md
// (header op,setup,tool,move,x,y,z,i,j,k; move = rapid|feed; x,y,z tool tip in mm; i,j,k unit tool axis from the tip
// towards the spindle).
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

enum class MoveKind { Rapid, Feed };

struct CutterLocation {
  int op = 0;         // operation index (plan.json's operations)
  int setup = 0;      // setup index
  std::string tool;   // tool id
  MoveKind move = MoveKind::Feed;  // how the tool gets to this point from the previous one
  Vec3 tip = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
};

using Toolpath = std::vector<CutterLocation>;

// One point of a path (op left 0: the plan numbers operations).
CutterLocation cutterLocation(int setup, const std::string& tool, MoveKind move, const Vec3& tip, const Vec3& axis);

// `value` in fixed notation with `decimals` decimals appended to `out`, "-0.000" written as "0.000" (the files people
// read: toolpaths.csv, trajectory.csv).
void appendFixed(std::string& out, double value, int decimals);

// Throws InputError with the file and line for a malformed file (missing column, NaN, axis not unit within 1e-3).
Toolpath readToolpathsCsv(const std::string& path);
void writeToolpathsCsv(const Toolpath& path, const std::string& file);
double toolpathLength(const Toolpath& path, MoveKind kind);  // mm of feed (or rapid) moves

}  // namespace art2part
