// Internal to the simulation's measures (surface_coverage.cpp, scallop_probe.cpp): the feed moves of a toolpath with
// their tools' cutting pieces, and the poses along a move.
#pragma once

#include <string>
#include <vector>

#include "art2part/simulation/tool_solid.h"
#include "art2part/tooling/toolpath.h"

namespace art2part::simulation_detail {

// The cutting part of a tool: its pieces of zone Flutes and their extent in the tool's frame.
struct Flutes {
  std::vector<ToolPiece> pieces;
  double h_min = 0, h_max = 0;  // lowest and highest height above the tip
  double radius = 0;            // widest
  // The outline's radius is a concave function of the height from the tip up (each piece convex, the slope never
  // growing from one piece to the next): the flutes are one convex solid, so the distance from a point to them along
  // a straight move of constant axis is a convex function of the move's parameter.
  bool convex = false;
  // Exact distance from a point at (h, rho) in the tool's frame to the flutes (0 inside): least over the pieces.
  double distance(double h, double rho) const;
};

// One feed move: the tool goes from `from` to `to` cutting (the tip straight, the axis turning in their plane).
struct FeedMove {
  int tool = 0;  // index into the tools given
  int row = 0;   // the toolpath row it ends at
  ToolPose from, to;
  double angle = 0;  // rad between the two axes
};

// The flutes of each tool (tool_solid.h pieces of zone Flutes) in the order given.
std::vector<Flutes> flutesOf(const std::vector<Tool>& tools);

// Every row that is a feed and continues the row before with the same tool and setup, as a move from that row's pose
// (a row after a tool change or a new setup places the tool: no motion). Throws InputError naming the row (and
// `who`) for a tool id `tools` lacks.
std::vector<FeedMove> feedMoves(const Toolpath& path, const std::vector<Tool>& tools, const std::string& who);

// Steps between the poses of a move so that no point of the flutes moves more than `step` from one to the next
// (the tip's travel plus the turn times the flutes' top height); at least 1.
int poseSteps(const FeedMove& move, const Flutes& flutes, double step);
// The pose at fraction f of the move (tip linear, axis by slerp in the plane of the two axes).
ToolPose poseAt(const FeedMove& move, double f);

// Axis-aligned box of the flutes at a pose (their bounding cylinder), grown by `grow` on every side.
Box flutesBox(const Flutes& flutes, const ToolPose& pose, double grow);
// A box holding the flutes all along the move: the two ends' boxes for a straight move; for a turning one the boxes
// of poses no flute point moves more than `step` between, grown by `step`.
Box moveBox(const FeedMove& move, const Flutes& flutes, double step);

// The distance from a point at height h above the tip and rho from the axis (rho >= 0) to the piece's solid of
// revolution, exact (0 inside): a planar distance to the piece's meridian outline.
double distanceToPiece(const ToolPiece& piece, double h, double rho);

}  // namespace art2part::simulation_detail
