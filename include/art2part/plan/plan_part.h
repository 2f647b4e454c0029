// The whole pipeline as one call, without ROS: visibility -> setups (the cover, then any added for finishing) -> holes
// -> roughing -> finishing -> verification
// (thesis chapters 3-4: from the part to a finished part's toolpaths, checked by simulation). The CLI's `plan` and
// the nodes call this; nothing else strings the stages together.
//
// Holes a drill or a helix makes are found first and kept out of roughing (their volume is added to the solid the
// roughing sees), so the drill meets solid stock. The combined toolpath runs setup by setup: each setup's roughing,
// then its finishing (each setup's points together, as the post needs), operation numbers across both. Roughing the
// simulation finds removing almost nothing is then left out when the plan without it verifies as clean
// (useless_operations.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "art2part/common/progress.h"
#include "art2part/finishing/finishing.h"
#include "art2part/finishing/finishing_setups.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/simulation/verify.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

struct PlanOptions {
  VisibilityOptions visibility;
  SetupOptions setups;
  RoughingOptions roughing;
  FinishingOptions finishing;  // its mode and allowance follow setups.mode and roughing.allowance
  FinishingSetupOptions finishing_setups;  // setups added beyond the cover for faces it leaves without their finish
  bool finish = true;          // false: the plan stops after roughing (and adds no setup for finishing)
  bool verify = true;          // simulate the whole path (verification.resolution 0: max(0.4, automatic, diagonal/300))
  bool drop_useless = true;    // with verify: roughing operations the simulation finds removing almost nothing are
                               // left out when the plan without them verifies as clean (useless_operations.h)
  int resume_checkpoints = 32;  // with drop_useless: copies of the stock the first verification keeps, at setup
                                // changes (every one, up to this many), for the trials without useless roughing to
                                // resume from (VerifyOptions::checkpoints)
  VerifyOptions verification;
};

// One operation of the combined plan, as plan.json lists it.
struct PlanOperation {
  int index = 0;               // position in the combined path (toolpaths.csv's op)
  int setup = 0;
  std::string kind;            // roughing | reach roughing | rest roughing | 5-axis roughing | face_mill | side_mill |
                               // contour | drill | helix | surface_3axis | surface_5axis | rest
  std::string tool;
  bool finishing = false;
  int source = -1;             // index into RoughingPlan::operations or FinishingPlan::operations
  std::size_t first_point = 0, points = 0;  // rows of the combined toolpath
};

// What became of the roughing operations the simulation found removing almost nothing (useless_operations.h).
struct UselessRoughing {
  int found = 0;           // roughing operations under kUselessRemovalShare of the roughing's volume
  bool dropped = false;    // some or all left out (RoughingPlan::dropped lists them): the plan without them verified
                           // as clean
  int kept = 0;            // found but kept: those of setups where the simulation without them finds something, or
                           // all of them
  std::string kept_why;    // why (the simulation without them, or the verification was cancelled)
};

struct PlanResult {
  VisibilityResult visibility;
  SetupPlan setups;
  std::vector<Hole> holes;
  std::vector<HoleMachining> hole_methods;
  RoughingPlan roughing;
  FinishingPlan finishing;
  std::vector<PlanOperation> operations;  // setup by setup: its roughing, then its finishing
  Toolpath toolpath;                      // every operation's points in that order, op numbers set
  std::vector<Tool> tools;                // every tool the path uses, in order of first use (tools.json)
  bool verified = false;
  VerificationReport verification;
  VerificationState simulation;           // the simulated stock, for pictures of what is left
  UselessRoughing useless;                // roughing the simulation found useless, and whether it was dropped
  std::vector<std::pair<std::string, double>> timings;  // stage, seconds, in order
  bool cancelled = false;                 // the progress sink asked to stop: the stages finished so far are kept
};

// Throws InputError for options out of range or a tool library without the tools roughing needs.
PlanResult planPart(const Part& part, const ToolLibrary& library, const PlanOptions& options = {},
                    const ProgressSink& progress = {});

// planPart's stages one by one, for a caller that runs them apart (the cell's stage nodes, chained by the supervisor
// through stage records: stage_records.h). planPart is exactly these in this order, so the cell plans what the CLI
// plans. Each throws what planPart throws for its stage.

// Setups: the minimum cover of the visibility cones, then (options.finish) the setups finishing adds beyond it.
SetupPlan planPartSetups(const Part& part, const VisibilityResult& visibility, const ToolLibrary& library,
                         const PlanOptions& options, const ProgressSink& progress = {});

// What roughing hands on: the holes a drill or a helix makes (found only when options.finish; roughing leaves them
// solid) and the roughing of the part with them plugged.
struct RoughingStage {
  std::vector<Hole> holes;
  std::vector<HoleMachining> hole_methods;  // one per hole
  RoughingPlan roughing;                    // its cancelled flag: the progress sink asked to stop
  double seconds_holes = 0;                 // of the stage's time, finding the holes and their methods
};
RoughingStage planPartRoughing(const Part& part, const SetupPlan& setups, const ToolLibrary& library,
                               const PlanOptions& options, const ProgressSink& progress = {});

// Finishing of every face, given the stages before it.
FinishingPlan planPartFinishing(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                const RoughingStage& roughing, const ToolLibrary& library, const PlanOptions& options,
                                const ProgressSink& progress = {});

// Fills the combined plan from its stages: operations setup by setup (roughing, then finishing, linked round the
// stock where the tool axis turns), the whole toolpath and the tools it uses (plan.json, toolpaths.csv, tools.json).
// Throws InputError for a tool the library lacks.
void combinePlan(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options);

// The verification planPart runs on a combined plan: its lattice (planVerifyResolution unless options say) and the
// faces' allowances (faceAllowances).
VerifyOptions planVerifyOptions(const Part& part, const PlanResult& plan, const ToolLibrary& library,
                                const PlanOptions& options);

// The part with the holes a drill or a helix makes filled (holePlugs), for roughing: triangles appended in face -1.
Part pluggedPart(const Part& part, const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods);

// The simulation's word on each face (its face_checks: the most material left on it): a face measured within 0.05 mm
// (the area figure's tolerance) by at least 3 rays is finished whatever the planner believed, one measured beyond it is
// partial; the reason says which. planPart calls it after verifying.
void judgeFaces(const VerificationReport& report, FinishingPlan& finishing);

// What a gouge may reach beyond the tolerance under each face (VerifyOptions::face_allowance): the concave faces'
// chord sag (concaveSag) and, on a drilled bore, how far its drill is over the bore's diameter, radially (a drill
// within HoleOptions::diameter_tolerance makes the hole).
std::vector<double> faceAllowances(const Part& part, const FinishingPlan& finishing, const ToolLibrary& library);

// The verification lattice a plan uses when none is asked for: at least 0.4 mm and 1/300 of the part's diagonal.
double planVerifyResolution(const Box& part_box);

}  // namespace art2part
