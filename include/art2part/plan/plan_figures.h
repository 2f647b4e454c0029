// What a plan costs on the machine and what each operation earns: the cycle time of the whole path (post/cycle_time.h)
// per operation, per setup and for the part, the volume each operation removed in the verification's simulation, and
// the bound it is judged against (that volume at its tool's library rate). plan.json and the cycle-time bench print
// these figures.
#pragma once

#include <string>
#include <vector>

#include "art2part/plan/plan_part.h"
#include "art2part/post/cycle_time.h"

namespace art2part {

// A roughing operation removing less than this share of what the whole roughing removes is useless: plan.json flags
// it, and planPart leaves it out when the plan without it verifies as clean (useless_operations.h).
constexpr double kUselessRemovalShare = 0.001;
// An operation's time against a bound under this many seconds says nothing (a ratio to nearly nothing): no ratio.
constexpr double kLeastBoundSeconds = 1.0;

struct OperationFigures {
  int index = 0;            // plan.operations' index (toolpaths.csv's op)
  bool finishing = false;
  CycleTime time;           // its moves and the tool change that starts it
  bool simulated = false;   // the plan was verified: the figures below are measured
  double removed_mm3 = 0;   // the stock its moves removed in the simulation
  double axial_depth_mm = 0;        // its level feeds' axial depth of cut (verify.h's kAxialDepthShare of them)
  double deepest_level_cut_mm = 0;  // the highest stock its level feeds removed above the tip (sweep.h)
  int gouges = 0, collisions = 0;   // its moves among the simulation's gouges and collisions
  int rapid_collisions = 0;         // of those, rapids through material
  double worst_collision_mm = 0;    // the deepest of its collisions
  double mm3_per_min = 0;   // removed_mm3 over its motion time (cutting and rapid)
  double bound_s = 0;       // removed_mm3 at its tool's library rate
  double bound_ratio = 0;   // its time over bound_s; 0 when bound_s is under kLeastBoundSeconds
  bool useless = false;     // a roughing operation removing under kUselessRemovalShare of the roughing's volume
  std::string useless_reason;
};

struct PlanFigures {
  MotionLimits limits;      // the machine's, as timed
  std::string machine;      // its name, or "default" (motionLimits' documented default)
  PathTime time;            // the whole path
  std::vector<OperationFigures> operations;  // one per plan.operations, in order
  CycleTime roughing, finishing;             // the operations of each stage summed (no setup changes)
  double roughing_removed_mm3 = 0, roughing_bound_s = 0;  // over the roughing operations (when simulated)
};

// The path timed on `machine` (each setup's frame along the machine's axes); a machine without joints: the default
// limits. Throws InputError for a tool the path uses but plan.tools lacks.
PlanFigures planFigures(const PlanResult& plan, const Machine& machine);

}  // namespace art2part
