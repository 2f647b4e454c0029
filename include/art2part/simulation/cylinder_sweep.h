// The sweep of a cylinder (a flat end mill's flutes) along a straight move: exact for a move square to its axis (a
// level move) or along it (a plunge or a lift), within a stated slack for a ramp.
//
// A level move sweeps a stadium extruded along the axis (an axial move, a cylinder the move's length taller): convex,
// so a ray meets it in one interval, found in closed form. Against the pose-by-pose sweep (sweep.h) it costs one
// interval per ray the solid covers instead of one per ray per pose (a level move of a 20 mm mill over 1.5 mm cells:
// 25 times fewer), and for a level or an axial move it removes the true swept volume, with no cusps between poses. It
// only removes: no gouge or collision is measured, so it serves a model of the stock a plan leaves (roughing's
// in-process stock), never the verification.
#pragma once

#include <vector>

#include "art2part/simulation/stock.h"
#include "art2part/simulation/tool_solid.h"

namespace art2part {

struct SweptCylinder {
  Vec3 from = Vec3::Zero();   // the tip at the move's start
  Vec3 to = Vec3::Zero();     // the tip at its end, level with `from`: to - from square to `axis`
  Vec3 axis = Vec3::UnitZ();  // unit
  double radius = 0;
  double h0 = 0, h1 = 0;  // the cylinder's heights above the tip along the axis, h0 < h1
};

// The sweep of `piece` (a cylinder: r0 == r1, no sphere) moved from `start` to `end` with the same axis, appended to
// `out`; false (and nothing appended) for any other piece or a turning move. A move along the axis is one cylinder as
// tall as the piece and the move (exact). Any other is cut in pieces whose rise or fall along the axis is at most
// `axial_slack` mm, each swept as a level move with its cylinder stretched by that rise or fall: exact for a level
// move, for a ramp a superset of the true sweep reaching at most `axial_slack` beyond it along the axis.
bool sweptCylinders(const ToolPiece& piece, const ToolPose& start, const ToolPose& end, double axial_slack,
                    std::vector<SweptCylinder>& out);

// Where the ray of family `axis` through `origin` (its coordinate along the ray does not matter) meets the solid, as
// coordinates along the ray; false when it misses it.
bool rayThroughSweptCylinder(const SweptCylinder& solid, int axis, const Vec3& origin, Span& out);

// Takes every solid out of `stock` (threads: 0 = the hardware's; each owns whole rows of every family, so the result
// does not depend on their count).
void removeSweptCylinders(Stock& stock, const std::vector<SweptCylinder>& solids, int threads = 0);

}  // namespace art2part
