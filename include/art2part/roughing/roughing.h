// Global roughing, 3-axis per setup (thesis 4.1, 5.1-5.2): the stock cleared around the part slab by slab from each
// setup's direction. At each level the tool centre may go where its disc, grown by the finishing allowance, meets no
// part material at or above the level (the shadow, offset by Clipper), where its shank and holder meet neither the
// part nor stock left above, and nowhere a level above forbade (so the column over every cutting point is clear);
// that region is cleared by zig-zag and contour passes (clearing_paths.h). Levels: a regular step-down plus the
// critical heights of the thesis's future work (every flat face square to the direction gets a level at its height
// plus the allowance). Tools: the largest flat or bull mill whose regions clear nearly what the smallest one does,
// then a rest pass with a smaller tool over what the first left.
#pragma once

#include "art2part/common/progress.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/roughing/clearing_paths.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

struct RoughingOptions {
  // The raw stock the setups start from.
  struct RawStock {
    double margin = 2.0;  // mm around the part's box (the verification's default), when there is no mesh
    std::shared_ptr<const Mesh> mesh;  // the raw stock instead of the box (its convex hull per slab is cleared)
    // Each setup starts from the stock the setups before it left (in_process_stock.h), not from the whole block.
    bool in_process = true;
    // The in-process stock's lattice (in_process_stock.h): about in_process_rays z-rays, but cells no coarser than
    // in_process_cell unless that needs more than in_process_max_rays. The model's film on what was cut grows with the
    // cell: a ray count alone made CTC-02's cells 5.4 mm.
    long in_process_rays = 20000;
    double in_process_cell = 1.5;  // mm
    long in_process_max_rays = 400000;
    // mm^2: a piece of a later setup's main pass (over the in-process stock) whose sweep takes less than this of the
    // stock the model proves is left out: a sliver of the centres a cutter's radius and a millimetre beyond proven
    // stock, which its sweep misses, cut for nothing at the price of a hop (mount_rush: 352 of 551 pieces under
    // 1 mm^2). Rest::least_target_mm2 is the rest passes' rule. 0 keeps every piece.
    double least_proven_mm2 = 1.0;
  };
  // Where the slabs of a setup lie.
  struct Levels {
    double stepdown = 0;            // mm between levels; 0 = the tool's max_stepdown (never above its flute length)
    bool critical_heights = true;   // a level at the height of every flat face square to the direction
    double critical_angle_deg = 0.5;  // a flat face within this of square to the direction gets a level
  };
  // How the main tool clears a level.
  struct Clearing {
    double stepover = 0;          // mm between zig-zag passes; 0 = the tool's max_stepover
    std::string tool;             // a tool id to use instead of choosing; empty = choose
    double tool_area_fraction = 0.85;  // the largest tool clearing at least this fraction of the best area
    double ramp_angle_deg = 3.0;  // entries into stock
    double clearance = 5.0;       // mm above the stock's top: the retract plane of each setup
    double holder_margin = 0.5;   // mm kept between shank or holder and material
    // Links between passes, pieces and levels inside cleared material or over stock the slabs prove clear
    // (clearing_paths.h, link_clearance.h), piece after piece, a pocket finished before the next
    // (operation_moves.h); false: every link over the clearance plane, level by level. The simulation finds no gouge
    // or collision in stay-down roughing on any shared part, and it cuts CTC-02's roughing time by 5 % and its rapids
    // by 20-45 % per operation.
    bool stay_down = true;
    // How the main pass clears a level. Engagement: with the largest of the library's high-efficiency cutters
    // (Tool::max_engagement_deg) that clears nearly what the smallest does, front by front under the cutter's
    // engagement limit at its own step-down and feed (engagement_clearing.h); where the library has none, as ZigZag.
    // ZigZag: a conventional end mill, zig-zag and contour passes a stepover apart. Rest passes are zig-zag always.
    // ZigZag by default until engagement clearing beats it on machine time on large parts: CTC-01's roughing takes
    // 72,073 s by engagement (main pass, step-up, rest passes) against 61,097 s by zig-zag (the step-up pass's thin
    // stair bands are linked by hops: 1,000 m of rapids for 167 m of cutting in setup 0).
    enum class Strategy { Engagement, ZigZag };
    Strategy strategy = Strategy::ZigZag;
    double corner_radius_ratio = 2.0;  // engagement: least radius of a front's turn round material, in tool radii
    // Engagement: after the main pass, a step-up pass ("adaptive rest roughing"): the same cutter, by engagement, over
    // what the main pass left beyond the allowance, at levels this share of its step-down apart. Its slabs are up to
    // 2 D deep and leave stairs that deep on faces at a slant to the direction; the conventional rest passes after it
    // then meet the stairs a zig-zag main pass leaves. 0: no step-up pass.
    double step_up_share = 0.25;
  };
  // Smaller tools over what the first left.
  struct Rest {
    bool enabled = true;          // rest passes after each setup's main operation
    int passes = 2;               // at most this many, each tool at most half the previous one (20 -> 10 -> 4 mm)
    // mm between a rest pass's levels (its tool's own step-down when that is less): re-roughing at fine levels takes
    // the stairs that big steps leave on faces at a slant to the direction, and cuts little elsewhere.
    double stepdown = 2.0;
    // mm^2: a piece of a rest pass's centre region whose sweep takes less than this of the stock it is to remove (the
    // previous operation's leftovers beyond the allowance) is left out: the tool would cut air round stock it cannot
    // reach. 0 keeps every piece.
    double least_target_mm2 = 1.0;
    // A rest pass planned to remove less than this share of what the setups' operations before it are planned to
    // remove is dropped (RoughingPlan::dropped), and the next rest tool starts from what it would have started from.
    // The planned removal bounds the true one from above (the slabs' stock holds at least the stock there is), so a
    // dropped pass removes less than this share in the simulation too. 0 keeps every pass.
    double least_removal_share = 0.001;
    // Before the rest passes, a reach pass: the longest-fluted flat mill of the main tool's diameter (flat20L after
    // flat20) over what the main pass left, at its own step-down, where the main tool's shank and holder kept it out
    // of deep pockets. Without it that stock falls to finishing's long tools, which take it at finishing feeds and
    // depths (CTC-02: a face-mill pass removing 1.2 L). Run only in setups deeper than the main tool's flutes, and
    // dropped as a rest pass is by least_removal_share, or when it is planned to remove stock at under
    // least_reach_rate_share of its tool's library rate (libraryRemovalRate): a reach pass tracing thin stock round
    // the part (featuretype: 6 cm3 in 525 s, 2.5 % of flat20L's rate) costs more than the finishing passes it spares.
    bool reach = true;
    double least_reach_rate_share = 0.1;
  };
  // 5-axis voxel roughing after each setup's 3-axis operations (voxel_roughing.h).
  struct FiveAxis {
    bool enabled = false;         // run it
    double max_tilt_deg = 60;     // the most the tool leans from the setup direction while cutting
    int cone_level = 3;           // sphere level of the voxels' visibility cones (256 directions at 3)
    double transition_sr = 0.01;  // least solid angle two neighbouring voxels' cones share for a move between them
  };

  double allowance = 0.3;       // mm left on the part for finishing
  double rapid_mm_min = 10000;  // rapid rate for time estimates
  RawStock stock;               // the raw stock and what earlier setups left of it
  Levels levels;                // the slabs of each setup
  Clearing clearing;            // the main tool and how it clears a level
  Rest rest;                    // rest passes
  FiveAxis five_axis;           // 5-axis voxel roughing
};

struct RoughingLevel {
  double z = 0;               // setup frame, mm
  bool critical = false;      // at a flat face's height (+ allowance)
  double cleared_mm2 = 0;     // area the tool sweeps at this level (centre region grown by the radius, in stock)
  double remaining_mm2 = 0;   // stock left in the slab above this level, part section included
  int rings = 0;              // rings of the centre region (machinable contours, offset)
};

struct RoughingOperation {
  int setup = 0;
  std::string kind;           // "roughing" | "adaptive roughing" | "adaptive rest roughing" | "reach roughing" |
                              // "rest roughing"
  std::string tool;
  Toolpath path;              // in the part frame; op numbers are set by the caller
  std::vector<RoughingLevel> levels;
  double feed_mm = 0, rapid_mm = 0, seconds = 0;  // length and estimated time
  int ramps = 0, plunges = 0, retracts = 0;  // ramp entries, straight entries into stock (passes too short to ramp), retracts
  double plan_seconds = 0;
  int direct_levels = 0;      // levels whose grown forbidden region missed part of the shadow (taken directly there)
  // The planner's slabs' stock within the tool radius of its centre regions, over each slab's height: at least what
  // it removes, since those slabs hold at least the stock there is.
  double planned_removal_mm3 = 0;
};

// An operation left out of the plan: a rest pass that would have removed almost nothing
// (RoughingOptions::Rest::least_removal_share), or a roughing operation the simulation found removing almost nothing
// (useless_operations.h).
struct DroppedOperation {
  int setup = 0;
  std::string kind, tool;
  double planned_removal_mm3 = 0;  // what it was planned to remove, at most
  double plan_seconds = 0;         // what planning it took (spent for nothing: what a faster rule would save)
  bool simulated = false;          // dropped by the simulation's figures: removed_mm3 and seconds hold
  double removed_mm3 = 0;          // what it removed in the simulation of the plan with it
  double seconds = 0;              // its estimated time, saved
  std::string reason;              // one line for plan.json
};
// The operation's setup, kind, tool and planned removal, left out for `reason`.
DroppedOperation droppedOperation(const RoughingOperation& op, std::string reason);

// The stock left in one slab [z, top] of a setup frame (part section included), projected along the direction.
struct SlabState {
  double z = 0, top = 0;
  Region remaining;           // stock left in the slab [z, top] after the operation (part section included)
};

struct RoughingPlan {
  std::vector<RoughingOperation> operations;
  // Per setup (index as in the setup plan), in its frame: the stock its 3-axis operations left, slab by slab from the
  // top (empty for a setup with no operation). What finishing must still expect in the way of shanks and rapids.
  std::vector<std::vector<SlabState>> stock_left;
  std::vector<DroppedOperation> dropped;  // operations planned and left out, in planning order
  double seconds = 0;
  int contours = 0;           // rings of centre regions over all levels
  int closed_open_mesh_edges = 0;  // the part's mesh was open: the edges of its boundary, closed (solid_closure.h)
  long region_failures = 0;   // Clipper operations that reported failure while planning (RegionFailureTally)
  int direct_levels = 0;      // levels over all operations whose grown forbidden region missed part of the shadow
  bool cancelled = false;     // the progress sink asked to stop: the setups finished before it are kept
};

// Where a roughing operation starts, beside its setup's block of stock.
class InProcessStock;
class SetupShadows;
struct RoughingStart {
  std::vector<SlabState> previous;         // a rest pass: what the operation before it left, slab by slab from the
                                           // top; empty: the setup's main operation
  const InProcessStock* earlier = nullptr; // what earlier setups left of the stock; none: the block as it is
  bool step_up = false;                    // with `previous`: the main pass's cutter again, by engagement, at
                                           // Clearing::step_up_share of its step-down (a step-up pass)
  bool reach = false;                      // with `previous`: a longer tool than the main pass's at its own
                                           // step-down (a reach pass, RoughingOptions::Rest::reach)
  SetupShadows* shadows = nullptr;         // the part's shadows in the setup's frame, shared by the setup's
                                           // operations (from the part roughed, machiningSolid); none: its own
  double least_removal_mm3 = 0;            // a pass planned to remove less (and something) is not written out:
                                           // RoughingPass::under_least_removal (Rest::least_removal_share)
};

// One operation and the stock it leaves.
struct RoughingPass {
  RoughingOperation operation;
  std::vector<SlabState> left;  // the stock after it, slab by slab from the top (a rest pass's `previous`)
  bool cancelled = false;       // the progress sink asked to stop: the levels planned so far
  // Planned to remove less than RoughingStart::least_removal_mm3: the operation's figures (planned removal, levels,
  // plan time) without its path, which would be written for nothing.
  bool under_least_removal = false;
};

// One operation: `tool` clears the stock of one setup top-down, level by level, restricted to `start`. Reports
// ("roughing", the share of its levels done, the level) to `progress` after each level and stops when it says so.
RoughingPass roughSetup(const Part& part, const Setup& setup, int setup_index, const Tool& tool,
                        const RoughingOptions& options, const RoughingStart& start = {},
                        const ProgressSink& progress = {});

// The levels of a setup for a tool: stock top down to the stock's bottom, at most `stepdown` apart, plus critical
// heights; highest first. `frame_vertices` are the part's vertices in the setup frame.
std::vector<RoughingLevel> roughingLevels(const Part& part, const std::vector<Vec3>& frame_vertices,
                                          double stock_top, double stock_bottom, double stepdown,
                                          const RoughingOptions& options);

// The tools a roughing operation may use (flat and bull end mills with flutes up to kRoughingFluteRatio diameters),
// largest first; and the choice for one setup.
constexpr double kRoughingFluteRatio = 3.0;
constexpr double kRoughingStepoverRatio = 0.4;  // stepover of a tool without max_stepover, in diameters
constexpr double kMostStepoverRatio = 0.9;      // passes must overlap or ridges stay between them
constexpr double kRestToolRatio = 0.5;          // a rest (or 5-axis) tool is at most this of the tool before it
constexpr double kSmallestRoughingTool = 3.0;   // mm: smaller mills step down a fifth of their diameter (finishing)
std::vector<const Tool*> roughingTools(const ToolLibrary& library);
// The choice measures each candidate against `shadows` (the part's in the setup's frame, shared with the setup's
// operations) over the stock `in_process` proves (none: the block); the first form takes shadows of its own.
const Tool* chooseRoughingTool(const Part& part, const Setup& setup, const std::vector<const Tool*>& candidates,
                               const RoughingOptions& options);
const Tool* chooseRoughingTool(const Part& part, const Setup& setup, const std::vector<const Tool*>& candidates,
                               const RoughingOptions& options, const InProcessStock* in_process,
                               SetupShadows& shadows);

// mm between the passes of `tool`: options.clearing.stepover, else the tool's max_stepover, else
// kRoughingStepoverRatio diameters; never above kMostStepoverRatio diameters.
double roughingStepover(const Tool& tool, const RoughingOptions& options);

// Every setup, main and rest operations, on machiningSolid(part). Throws InputError for a tool id that the library
// lacks or that cannot rough. Reports to `progress` after every level (stage "roughing", the share of the setups
// done, "setup k of n: <kind>, <tool>, level i of m"; ProgressReport::done counts the levels planned so far); when it
// asks to stop, returns the setups finished so far with `cancelled` set.
RoughingPlan planRoughing(const Part& part, const SetupPlan& setups, const ToolLibrary& library,
                          const RoughingOptions& options = {}, const ProgressSink& progress = {});

// The stock of the plan in the part frame: the part's box grown by the margin, or the stock mesh.
Mesh roughingStock(const Part& part, const RoughingOptions& options);

// Takes away from `stock` what the operations of setups `first` to `last` cut (each with its tool from `library`):
// the stock a later setup starts from, or finishing sees along any direction (stock_after_roughing.h).
void removeOperations(InProcessStock& stock, const std::vector<RoughingOperation>& operations,
                      const ToolLibrary& library, int first, int last);

}  // namespace art2part
