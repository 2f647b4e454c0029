// Verification: any toolpath (ours or a third party's, through the toolpaths.csv + tools.json contract) simulated
// against the part: gouges, collisions, what is left. A planner is never its own judge.
//
// The chain: the stock (a box with margins around the part, or a mesh) and the part dexelized on one tri-dexel lattice
// (stock.h, mesh_dexels.h); the toolpath swept through it (sweep.h); the leftover measured (leftover.h); the remaining
// stock contoured and coloured by its deviation when asked (stock_mesh.h). The report is plain data; reportJson gives
// the CLI's JSON (`art2part verify`).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "art2part/common/progress.h"
#include "art2part/geometry/mesh.h"
#include "art2part/simulation/leftover.h"
#include "art2part/simulation/stock.h"
#include "art2part/simulation/sweep.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

struct VerificationReport;

struct VerifyOptions {
  double resolution = 0;       // mm, lattice spacing; 0 = automatic (about 1.5 M rays, at least 0.1 mm)
  double tolerance = 0.01;     // mm: gouges and collisions deeper than this count
  double stock_margin = 2.0;   // mm around the part's box, when no stock mesh is given
  const Mesh* stock_mesh = nullptr;  // the raw stock instead of a box (the part is always inside it)
  double step_fraction = 0.5;  // sub-step bound, of the resolution (sweep.h)
  bool cusp_step = true;       // and the cusp bound (sweep.h)
  int threads = 0;             // 0 = the hardware's
  int max_listed = 100;        // entries per list in the report (the totals count them all)
  double tool_chord_mm = 0.001;  // how closely a bull mill's torus corner is followed
  // Per face id: how much deeper than the tolerance a gouge under that face may go before it counts: the chords' sag
  // of a concave curved face (concaveSag, face.h: cutting its true surface cuts that deep into the mesh), and what a
  // drilled bore's drill may be over its diameter, radially. Empty: none.
  std::vector<double> face_allowance;
  // Sweep checkpoints kept in VerificationState::checkpoints for a later verification to resume from (below): at
  // most this many, at setup changes spread evenly over the path's rows (at every one when there are no more of
  // them), each a copy of the stock. 0: none.
  int checkpoints = 0;
  // Asked at each checkpoint row (above) the sweep reaches, with the report of the rows before it (its gouges,
  // collisions and by_op counted as the whole report counts them; nothing measured): false stops the sweep there
  // (VerificationReport::stopped_at_row). Unset: the whole path. A trial that only needs to know where the first
  // finding lies (useless_operations.h) stops there; the stage records do not carry it (a service sweeps it all).
  std::function<bool(int row, const VerificationReport& so_far)> keep_sweeping;
};

struct GougeRecord {
  int point = 0;  // row of toolpaths.csv (0 = first data row): the move ending there
  int op = 0, setup = 0;
  std::string tool;
  double depth_mm = 0;
  Vec3 position = Vec3::Zero();  // the deepest removed point of the part
  Vec3 tip = Vec3::Zero();       // the tool tip at that pose
};

struct CollisionRecord {
  int point = 0, op = 0, setup = 0;
  std::string tool;
  CollisionKind kind = CollisionKind::Shank;
  double depth_mm = 0;           // how far the material reaches into the shank, holder or (rapid) tool
  Vec3 position = Vec3::Zero();  // the deepest point of material met
  Vec3 tip = Vec3::Zero();
};

// One face of the part after the whole path (issue 17 item 9: roughing and finishing simulated in order): the material
// left on it and the deepest gouge under it.
struct FaceVerification {
  int face = -1;
  double left_max_mm = 0;   // the largest material left above the face: leftover.h's FaceCusp (thickness met just
  double left_mean_mm = 0;  // outside the face along rays within 60 deg of its normal), max and mean
  int samples = 0;          // those rays (0: no ray crossed the face steeply enough to measure it)
  int gouges = 0;           // moves whose deepest gouge (deeper than the tolerance) lies under this face
  double deepest_gouge_mm = 0;                 // the deepest of them (0 when none)
  Vec3 deepest_gouge_point = Vec3::Zero();     // where (inside the part)
};

// The share of an op's level cutting under the height reported as its axial depth of cut (levelCutDepth): the rest
// is hairs shaved off walls above the slab, which the highest point alone would report.
constexpr double kAxialDepthShare = 0.99;

// What the simulation found of one toolpath op.
struct OperationCheck {
  OperationSweep swept;            // what it removed, and how deep its level feeds cut (sweep.h)
  int gouges = 0, collisions = 0;  // its moves among the report's gouges and collisions
  int rapid_collisions = 0;        // of those collisions, rapids through material (the rest: shank or holder rubbing)
  double worst_collision_mm = 0;   // the deepest of its collisions
};

struct VerificationReport {
  int gouges = 0;  // moves removing part material deeper than the tolerance
  double worst_gouge_mm = 0;
  std::vector<GougeRecord> gouge_list;  // deepest first, at most max_listed
  int collisions = 0;                   // moves whose shank or holder meets material, or rapids through it
  double worst_collision_mm = 0;
  std::vector<CollisionRecord> collision_list;  // in path order, at most max_listed
  double leftover_volume_mm3 = 0;
  double leftover_max_mm = 0;
  std::vector<LeftoverRegion> regions;  // largest first, at most max_listed
  int region_count = 0;
  std::vector<FaceCusp> faces;  // highest cusp first, at most max_listed
  int face_count = 0;
  // Every face id of triangle_face (0 .. the largest), by id, never cut to max_listed; empty without triangle_face.
  // A gouge goes to the face of the part triangle nearest its deepest point (PartDistance); a gouge nearest a
  // triangle of no face (-1, or one solid_closure.h added) is in the totals only.
  std::vector<FaceVerification> face_checks;
  // Figures.
  double resolution_mm = 0, tolerance_mm = 0;
  Vec3 spacing = Vec3::Zero();
  std::int64_t dexels = 0;
  int moves = 0;
  std::int64_t poses = 0;
  double seconds_sweep = 0, seconds_total = 0, moves_per_second = 0;
  Box stock_box;
  double stock_volume_mm3 = 0, removed_volume_mm3 = 0, remaining_volume_mm3 = 0, part_volume_mm3 = 0;
  std::map<int, OperationCheck> by_op;  // by toolpath op, every op of the path (never cut to max_listed)
  int closed_open_mesh_edges = 0;  // the part's mesh was open: its boundary chain's edges, closed as solid_closure.h says
  int resumed_at_row = 0;  // the sweep began here, from a checkpoint (0: at the first row); moves_per_second counts
                           // the rows swept in this call

  bool cancelled = false;  // the progress sink asked to stop: the findings of the moves swept so far, nothing left
                           // measured; never passed
  int stopped_at_row = 0;  // VerifyOptions::keep_sweeping stopped the sweep before this row (0: it went on to the end):
                           // the findings of the rows before it, nothing left measured; never passed

  bool passed() const { return gouges == 0 && collisions == 0 && !cancelled && stopped_at_row == 0; }
};

// The sweep as it stood before a row where the tool is placed (a setup change), kept so that a later verification of a
// path whose rows before it are the same starts there instead of at the first row: a plan tried without operations
// it may not need (useless_operations.h) is swept the same up to the first one left out. A checkpoint is only used
// when its key matches: a hash of the rows before it and of everything else the sweep depends on (the lattice, the
// part and stock meshes, the tools' shapes, tolerance, step and chord).
struct SweepCheckpoint {
  int row = 0;                            // the first row not yet swept
  std::uint64_t key = 0;                  // of rows [0, row) and the sweep's inputs
  Stock stock;                            // before that row
  std::map<int, MoveFinding> findings;    // of the rows before it (SweepResult::findings)
  std::map<int, OperationSweep> by_op;    // of the ops before it (setup changes: no op goes on past it)
  std::int64_t poses = 0;
};

// What verifyToolpath keeps for outputs beyond the report (the picture, the remaining stock's mesh), and the
// checkpoints VerifyOptions::checkpoints asks for.
struct VerificationState {
  Stock stock;
  MeshDexels part;
  std::vector<SweepCheckpoint> checkpoints;  // by row
};

// `triangle_face`: the face of each part triangle (for cusps per face; may be empty). Throws InputError for a tool id
// the toolpath uses but `tools` lacks, a tool that cannot exist, an empty path, or a resolution that is too fine.
// Reports to `progress` (stage "verification"): before the lattice is built, during the sweep every
// kSweepReportSeconds with the share of the moves swept (sweep.h), and before the leftover is measured; when it asks
// to stop, returns within a second with `cancelled` set.
// `resume_from`: an earlier verification's checkpoints (VerificationState::checkpoints); the sweep starts from the
// latest whose key matches this call's, and the report is the one the whole sweep gives (test_simulation checks it).
VerificationReport verifyToolpath(const Mesh& part, const std::vector<int>& triangle_face, const Toolpath& path,
                                  const std::vector<Tool>& tools, const VerifyOptions& options = {},
                                  VerificationState* state = nullptr, const ProgressSink& progress = {},
                                  const std::vector<SweepCheckpoint>& resume_from = {});

// The lattice spacing `resolution = 0` stands for: about 1.5 M rays over the box, never finer than 0.1 mm.
double automaticResolution(const Box& box);

// The report as JSON text (indented): gouges, worst_gouge_mm, collisions, leftover_volume_mm3, leftover_max_mm,
// passed, the lists, face_checks (every face: face, left_max_mm, left_mean_mm, samples, gouges, deepest_gouge_mm,
// deepest_gouge_point) and the figures.
std::string reportJson(const VerificationReport& report);

}  // namespace art2part
