// Face-based finishing (thesis 4.2-4.3, with the tool selection and holder interference of its future work, 6.1):
// after global roughing, every face is targeted on its own, by the strategy its shape and the tools admit and from a
// direction that both admits it and reaches it (permissible = admissible and accessible, admissible.h):
//   plane square to a setup direction   face milling with the flat bottom: passes over the face, a contour round it
//   plane parallel to one               side milling with the flank, its depth within the flute length, least depth first
//   cylinder or extrusion along one     peripheral contour passes (climb), tool radius within the least concave radius
//   hole a drill matches                spot, drill, peck (holes.h); other round holes: helical milling
//   anything else                       ball or bull surface finishing to a scallop (surface_finishing.h), 3-axis per
//                                       setup or, in 5-axis mode, with the axis tilted from the face's cone
// then rest finishing of what each tool left with smaller tools, down to the smallest in the library. The largest
// tool that fits a group of faces finishes it (profiled against the part and the stock roughing left, shank and
// holder included); neighbouring faces of one direction share it; operations are ordered per setup so each tool is
// loaded once per setup. Every face ends with its operations and tools, or unmachinable with the reason.
//
// The planner's areas are its belief; the simulation of roughing and finishing together is the judge (verify.h,
// surface_coverage.h, scallop_probe.h).
#pragma once

#include <string>
#include <vector>

#include "art2part/common/progress.h"
#include "art2part/finishing/holes.h"
#include "art2part/finishing/surface_finishing.h"
#include "art2part/geometry/part.h"
#include "art2part/roughing/roughing.h"
#include "art2part/roughing/shadow.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

enum class FinishingKind { FaceMill, SideMill, Contour, Drill, Helix, Surface3Axis, Surface5Axis, Rest };
// face_mill | side_mill | contour | drill | helix | surface_3axis | surface_5axis | rest: plan.json's operation kind.
const char* finishingKindName(FinishingKind kind);

// Plane and cylinder faces with flat end mills.
struct PlanarFinishingOptions {
  double square_angle_deg = 0.1;   // a plane within this of square to (or parallel to) a direction counts as such
  double floor_stepover = 0.7;     // of the tool's diameter, between face milling passes
  double band_margin = 2.5;        // mm: a wall contour level finishes the wall up to the flutes' top less this (more
                                   // than the 2 mm the shank's bottom is rounded down by, planar_finishing.cpp)
  double link_gap = 2.0;           // mm: contour stretches closer than this along their ring are cut as one
};

// Which tools finish what.
struct FinishingToolOptions {
  double area_fraction = 0.9;      // the largest tool reaching this fraction of the area the smallest one reaches
  int max_rest_tools = 4;          // rest finishing: at most this many smaller tools per group after the first (20 mm
                                   // halving down to the library's 1 mm takes four)
  double holder_margin = 0.5;      // mm between shank or holder and material
};

struct FinishingOptions {
  MachineMode mode = MachineMode::ThreeAxis;
  double allowance = 0.3;          // mm roughing left on the faces (RoughingOptions::allowance)
  double clearance = 5.0;          // mm above the stock's top: the retract plane of each direction
  double rapid_mm_min = 10000;     // for the time estimates
  double tool_change_s = 10;       // seconds per tool change, for the time estimates
  int threads = 0;                 // groups of faces (a setup's direction) planned side by side, 0 = the hardware's;
                                   // the plan is the same for any count
  PlanarFinishingOptions planar;
  SurfaceFinishingOptions surface;
  HoleOptions holes;
  FinishingToolOptions tools;
};

struct FinishingOperation {
  int setup = 0;
  FinishingKind kind = FinishingKind::FaceMill;
  std::string tool;
  Vec3 direction = Vec3::UnitZ();  // tool axis (part frame); a 5-axis operation's axis varies around it
  std::vector<int> faces;          // faces it finishes, wholly or in part
  Toolpath path;                   // part frame; op numbers are set by the caller
  double feed_mm = 0, rapid_mm = 0, seconds = 0;  // length and estimated time (feeds from the library)
  double plan_seconds = 0;
  std::string note;                // why this strategy, when it is not the face's first choice
};

enum class FaceStatus {
  Finished,      // every part of it has an operation
  Partial,       // operations reach some of it; the rest needs a smaller tool or another direction
  Unmachinable,  // no operation reaches it
};
const char* faceStatusName(FaceStatus status);  // finished | partial | unmachinable

struct FaceFinish {
  int face = -1;
  FaceStatus status = FaceStatus::Unmachinable;
  FinishingKind strategy = FinishingKind::Surface3Axis;  // the first operation's kind
  int setup = -1;                  // the setup it is finished in (-1: none)
  Vec3 direction = Vec3::Zero();   // the tool axis chosen for it (zero: none), an arrow in rviz
  std::vector<int> operations;     // indices into FinishingPlan::operations
  std::vector<std::string> tools;  // in the order they touch it
  double area_mm2 = 0;
  double planned_mm2 = 0;          // what the planner believes its operations reach
  double radius_needed_mm = -1;    // Partial: the largest tool radius that would reach the rest (0: a sharp corner
                                   // no end mill makes); -1: not known
  std::string reason;              // Partial, Unmachinable: no permissible direction, radius below the smallest
                                   // tool, too deep for every tool, holder collision, ...
  // The simulation's word, when the plan was verified: the most material it finds left on the face, over `samples`
  // rays (0: none crossed it steeply enough to measure); the status follows it (planPart).
  double simulated_left_mm = -1;
  int samples = 0;
};

struct FinishingPlan {
  std::vector<FinishingOperation> operations;  // in machining order: setup by setup, each tool's operations together
  std::vector<FaceFinish> faces;               // one per face of the part, by face id
  std::vector<Hole> holes;                     // as made: a through hole reached from its far end turned round
  std::vector<HoleMachining> hole_methods;     // one per hole
  std::vector<int> tool_changes_per_setup;     // loads of a tool within each setup's finishing
  int tool_changes = 0;
  double seconds = 0;                          // estimated machining time, tool changes included
  double plan_seconds = 0;
  bool cancelled = false;                      // the progress sink asked to stop: operations so far are kept
};

// What finishing starts from: the part (as given: faces and triangles of the contract), its visibility, its setups,
// the holes found before roughing (and kept out of it) and the roughing plan with the stock each setup left.
struct FinishingInput {
  const Part& part;
  const VisibilityResult& visibility;
  const SetupPlan& setups;
  const RoughingPlan& roughing;
  const std::vector<Hole>& holes;
  const std::vector<HoleMachining>& hole_methods;
  const ToolLibrary& library;
};

// The whole stage. Throws InputError for options out of range or input that does not belong together (visibility of
// another mesh). A cancel from `progress` returns the operations so far with cancelled set.
FinishingPlan planFinishing(const FinishingInput& input, const FinishingOptions& options = {},
                            const ProgressSink& progress = {});

// What roughing left beyond `skin` on the part, slabs top down: the stock a finishing tool's shank, holder and links
// keep clear of, and planar finishing feeds down through. Each slab's region less the band within the skin and a
// slack of 0.05 mm (the outlines' arcs) around the part's shadow over the slab (shadow.h: the part at and above the
// slab's bottom), slivers under 0.02 mm dropped; slabs left empty are left out. Stock standing apart from the part
// stays whole however thin. The band needs no keeping: a shank or tool column over it comes within the skin of the part, which
// the part's own clearance (skin plus a margin) keeps it from. `frame_vertices`: the part's vertices in the slabs'
// frame.
std::vector<SlabState> stockBeyondSkin(const std::vector<SlabState>& stock_left, double skin,
                                       const std::vector<Vec3>& frame_vertices, const std::vector<Triangle>& triangles);
// The same with the part's shadows at the slabs' bottoms (slabShadows): one stack for several skins.
std::vector<SlabState> stockBeyondSkin(const std::vector<SlabState>& stock_left, double skin,
                                       const ShadowStack& shadows);
// The part's shadows (`frame_vertices` in the slabs' frame) at the bottoms of `slabs`.
ShadowStack slabShadows(const std::vector<SlabState>& slabs, const std::vector<Vec3>& frame_vertices,
                        const std::vector<Triangle>& triangles);

}  // namespace art2part
