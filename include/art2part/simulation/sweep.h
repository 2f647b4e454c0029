// Sweeping a toolpath through the stock: material removal, gouges and collisions, move by move.
//
// Each move is cut as a sequence of tool poses: the tip interpolated linearly, the axis by a rotation in the plane of
// the two axes (slerp). The sub-step bound: a move from (T0, a0) to (T1, a1) takes
//     n = ceil((|T1 - T0| + angle(a0, a1) * reach) / (step_fraction * resolution))
// poses, reach being the farthest any tool point that can be inside the stock lies from the tip (the tool's length and
// radius, capped by the distance from the tip to the farthest corner of the stock box). A point of the tool at
// distance rho from the tip moves by at most |dT| + dangle * rho between poses, so no point of the outline moves more
// than step_fraction * resolution (default half the finest lattice spacing) from one pose to the next, at any height,
// rotations about the tip included. What a swept solid removes between two poses is then at most a cusp of
// step^2 / (8 r) (r the radius of the outline there): 0.0004 mm for a 6 mm tool at 0.2 mm resolution. The step is
// also held to sqrt(4 rho tolerance) (rho the flutes' widest radius), so cusps stay under half the tolerance at coarse
// lattices too.
// When the axis does not turn, one direction of the motion costs no sub-steps, chosen per family of rays (the three
// are independent), whichever leaves the fewest:
//  - along the tool axis: a solid of revolution swept along its own axis is exactly itself plus a cylinder of its top
//    radius per piece (SweepPose::rise), so a plunge or a lift is one pose however deep;
//  - along the family's rays: the tool sliding along a ray covers the span it cuts there, stretched by the slide
//    (SweepPose::slide), so a long move along x is one pose for the x rays however long.
// Only the rest of the motion counts in |T1 - T0| above. A pose holds that rest at its end while the free part runs,
// which is off the move's line by up to |rest| |free| / (n |T1 - T0|) for n poses: n is raised until that is at most
// half the tolerance, so the sweep never cuts a gouge that the path does not (a diagonal move sliding in two poses
// at a 1.6 mm lattice was 0.68 mm off before this bound).
//
// At each pose every piece of the tool meets only the rays inside its bounding box (clipped to the stock), each ray
// analytically (tool_solid.h). Rays where the piece cannot meet material are passed over without changing anything:
// a tile of rays whose material all lies beyond the box along them, a ray whose material does, or whose widest stretch
// of air between two spans holds the box's range or the piece's swept span (a finishing tool's flutes over a pocket).
// Flutes remove material; material of the part they remove is a gouge, its depth the exact distance from the deepest
// removed point to the part's surface (the ends of each removed span inside the part, and up to 8 points between: a
// 0.05 mm dip reads 0.05 whatever the ray direction), deeper than the tolerance to count. The shank or the holder in
// remaining material, or any part of the tool in material during a rapid move, is a collision, its depth how far the
// material reaches into that piece of the tool (deeper than the tolerance to count). Material the tool meets during a
// rapid is removed too, so one crash is reported once, not by every later move.
// A move is swept only when it continues the previous row's tool and setup; otherwise the tool is placed at its point
// (a tool change or a new setup is no motion through the part frame).
//
// Threads share the stock by rows: each owns interleaved blocks of rows in each family and sweeps the whole path over
// them, so no ray is touched by two threads and the result does not depend on the thread count.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "art2part/common/progress.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/stock.h"
#include "art2part/simulation/tool_solid.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

enum class CollisionKind { Shank, Holder, Rapid };
const char* collisionKindName(CollisionKind kind);

// The worst of one move's poses.
struct MoveFinding {
  double gouge_mm = 0;  // > tolerance when the move gouges
  Vec3 gouge_point = Vec3::Zero(), gouge_tip = Vec3::Zero();
  double collision_mm = 0;  // > tolerance when the move collides
  CollisionKind collision = CollisionKind::Shank;
  Vec3 collision_point = Vec3::Zero(), collision_tip = Vec3::Zero();
};

struct SweepOptions {
  double tolerance = 0.01;     // mm: deeper gouges and collisions count
  double step_fraction = 0.5;  // of the finest lattice spacing: the most any tool point moves between poses
  bool cusp_step = true;       // also hold the step to sqrt(4 rho tolerance) (cusps under half the tolerance)
  int threads = 0;             // 0 = the hardware's
  // The rows swept: [first_row, end_row), end_row -1 for the path's end. Both ends are the path's ends or rows where
  // the tool is placed (toolPlacedAt), so a path swept in pieces leaves the stock and findings it leaves in one sweep;
  // the stock given is the stock as it stood before first_row. Other rows: InputError.
  int first_row = 0;
  int end_row = -1;
};

constexpr double kLevelCutBinMm = 0.25;  // the height bins of OperationSweep::level_cut_by_height_mm3

// What one toolpath op did to the stock in the sweep.
struct OperationSweep {
  // The stock its moves removed, mm^3 (Stock::volume's measure: the mean over the three families), so the ops'
  // figures sum to the stock's volume before the sweep less after it.
  double removed_mm3 = 0;
  // Its level cuts: what its flutes removed during feeds that keep the tip's height along a fixed axis (all of
  // 3-axis roughing's cutting), by height above the tip along the axis. Every point removed belongs to the tool within
  // the sweep's deviation (tolerance / 2) of a pose on the move, whose tip is at the move's height, so heights are
  // within tolerance / 2 of the truth. Stock removed above the step-down stood above the slab: the column over the
  // cut was not clear. The highest point alone says little (a hair shaved off a wall the full height of the flutes
  // counts), so the volume by height says how much of the cutting was that deep.
  double deepest_level_cut_mm = 0;  // the highest point removed, mm (0: no level feed cut)
  int deepest_level_cut_row = -1;   // the toolpath row ending the move that cut it (-1: none)
  // Bin b: the stock removed at heights [b, b + 1) x kLevelCutBinMm above the tip, mm^3 (a span removed along a ray
  // is spread evenly over the heights it spans); they sum to what its level feeds removed.
  std::vector<double> level_cut_by_height_mm3;
};

// The stock an op's level feeds removed at least `height` above the tip (whole bins at or above it: short of the
// truth by at most the bin that straddles it), mm^3.
double levelCutAbove(const OperationSweep& op, double height);
// The height under which `share` of what an op's level feeds removed lies (a bin's upper edge), mm; 0 when none.
double levelCutDepth(const OperationSweep& op, double share);

struct SweepResult {
  std::map<int, MoveFinding> findings;  // by row of the toolpath (the point the move ends at), moves at fault only
  std::int64_t poses = 0;
  double seconds = 0;
  bool cancelled = false;  // the progress sink asked to stop: the findings and the stock of the moves swept so far
  std::map<int, OperationSweep> by_op;  // by toolpath op, every op whose moves were swept
};

// Tools by id; throws InputError naming the row for a tool id that is not there. The threads all sweep (runTicking)
// while the calling thread, given a progress sink, reports (stage "verification", the share of the moves every thread
// has swept, "move i of n") every kSweepReportSeconds and stops them within a move when the sink says so; the sink is
// only ever called from the calling thread.
constexpr double kSweepReportSeconds = 0.25;
SweepResult sweepToolpath(Stock& stock, const MeshDexels& part, const PartDistance& part_distance,
                          const Toolpath& path, const std::map<std::string, ToolSolid>& tools,
                          const SweepOptions& options = {}, const ProgressSink& progress = {});

// Consecutive moves along one straight line (same op, tool, setup, kind of move and axis, same direction) are swept as
// one segment: the sweep of a segment does not depend on how many points lie on it. Findings go to the move whose
// stretch of the line holds the point found.
struct StraightRun {
  int first = 0, last = 0;  // the moves ending at rows first..last; the run starts at row first - 1
  bool placed = false;      // first is a tool placed at its point (first row, new tool or setup): no motion
};
std::vector<StraightRun> straightRuns(const Toolpath& path);

// Whether row `row` places the tool at its point (the first row, a new tool or a new setup) rather than moving to it.
bool toolPlacedAt(const Toolpath& path, int row);

// A pose of the sweep for one family of rays: the tool at `pose`, and also everywhere up to `rise` mm further up its
// axis, and everywhere between `pose` and `pose` moved back by `slide` mm along the family's axis.
struct SweepPose {
  ToolPose pose;
  double rise = 0;   // >= 0
  double slide = 0;  // signed: the motion along the family's axis this pose stands for
};

// The poses a move passes through after its start (its end included) for the rays along `axis`, by the bounds above
// (`deviation`: how far beyond the true sweep a rise or a slide may reach).
std::vector<SweepPose> movePoses(const ToolPose& from, const ToolPose& to, const ToolSolid& tool, const Box& stock_box,
                                 double step, double deviation, int axis);

}  // namespace art2part
