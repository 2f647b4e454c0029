#include "art2part/simulation/verify.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "art2part/geometry/solid_closure.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/part_distance.h"
#include "sweep_checkpoints.h"

namespace art2part {

namespace {

constexpr double kAutomaticRays = 1.5e6;
constexpr double kFinestAutomatic = 0.1;
// The stage's progress: the lattice and the stock up to kSweepStart, the sweep up to kSweepEnd, then the leftover.
constexpr double kSweepStart = 0.1, kSweepEnd = 0.9;

Box unite(Box a, const Box& b) {
  if (!b.empty()) {
    a.extend(b.min);
    a.extend(b.max);
  }
  return a;
}

Stock initialStock(const Mesh* stock_mesh, const DexelLattice& lattice, const MeshDexels& part) {
  Stock stock = stock_mesh ? meshStock(MeshDexels(*stock_mesh, lattice)) : boxStock(lattice);
  addSolid(stock, part);
  return stock;
}

std::map<std::string, ToolSolid> toolSolids(const std::vector<Tool>& tools, double chord) {
  std::map<std::string, ToolSolid> solids;
  for (const Tool& tool : tools) solids[tool.id] = toolSolid(tool, chord);
  return solids;
}

// The face under a gouge's deepest point (the nearest triangle's), -1 when none.
int gougeFace(const MoveFinding& f, const std::vector<int>& triangle_face, const PartDistance& distance) {
  int triangle = -1;
  distance.distance(f.gouge_point, &triangle);
  return triangle >= 0 && triangle < static_cast<int>(triangle_face.size()) ? triangle_face[triangle] : -1;
}

// A move's gouge counts when deeper than the tolerance and the allowance of the face under it.
bool countsAsGouge(const MoveFinding& f, double tolerance, const std::vector<double>& allowance,
                   const std::vector<int>& triangle_face, const PartDistance& distance) {
  if (!(f.gouge_mm > tolerance)) return false;
  if (allowance.empty()) return true;
  const int face = gougeFace(f, triangle_face, distance);
  return face < 0 || face >= static_cast<int>(allowance.size()) || f.gouge_mm > tolerance + allowance[face];
}

void listFindings(VerificationReport& r, const std::map<int, MoveFinding>& findings, const Toolpath& path,
                  double tolerance, const std::vector<double>& allowance, const std::vector<int>& triangle_face,
                  const PartDistance& distance, int max_listed) {
  for (const auto& [point, f] : findings) {
    const CutterLocation& row = path[point];
    if (countsAsGouge(f, tolerance, allowance, triangle_face, distance)) {
      ++r.gouges;
      ++r.by_op[row.op].gouges;
      r.worst_gouge_mm = std::max(r.worst_gouge_mm, f.gouge_mm);
      r.gouge_list.push_back({point, row.op, row.setup, row.tool, f.gouge_mm, f.gouge_point, f.gouge_tip});
    }
    if (f.collision_mm > tolerance) {
      ++r.collisions;
      OperationCheck& check = r.by_op[row.op];
      ++check.collisions;
      if (f.collision == CollisionKind::Rapid) ++check.rapid_collisions;
      check.worst_collision_mm = std::max(check.worst_collision_mm, f.collision_mm);
      r.worst_collision_mm = std::max(r.worst_collision_mm, f.collision_mm);
      if (static_cast<int>(r.collision_list.size()) < max_listed)
        r.collision_list.push_back(
            {point, row.op, row.setup, row.tool, f.collision, f.collision_mm, f.collision_point, f.collision_tip});
    }
  }
  std::stable_sort(r.gouge_list.begin(), r.gouge_list.end(),
                   [](const GougeRecord& a, const GougeRecord& b) { return a.depth_mm > b.depth_mm; });
  if (static_cast<int>(r.gouge_list.size()) > max_listed) r.gouge_list.resize(max_listed);
}

// Per face: the leftover's cusps, and each counted gouge at the face of the triangle nearest its deepest point.
std::vector<FaceVerification> checkFaces(const LeftoverAnalysis& leftover, const std::map<int, MoveFinding>& findings,
                                         const std::vector<int>& triangle_face, const PartDistance& distance,
                                         double tolerance, const std::vector<double>& allowance) {
  int faces = 0;
  for (int f : triangle_face) faces = std::max(faces, f + 1);
  std::vector<FaceVerification> checks(faces);
  for (int f = 0; f < faces; ++f) checks[f].face = f;
  for (const FaceCusp& cusp : leftover.faces) {
    if (cusp.face < 0 || cusp.face >= faces) continue;
    checks[cusp.face].left_max_mm = cusp.max_mm;
    checks[cusp.face].left_mean_mm = cusp.mean_mm;
    checks[cusp.face].samples = cusp.samples;
  }
  for (const auto& [point, f] : findings) {
    if (!countsAsGouge(f, tolerance, allowance, triangle_face, distance)) continue;
    const int face = gougeFace(f, triangle_face, distance);
    if (face < 0 || face >= faces) continue;
    FaceVerification& check = checks[face];
    ++check.gouges;
    if (f.gouge_mm > check.deepest_gouge_mm) {
      check.deepest_gouge_mm = f.gouge_mm;
      check.deepest_gouge_point = f.gouge_point;
    }
  }
  return checks;
}

void listLeftover(VerificationReport& r, LeftoverAnalysis leftover, int max_listed) {
  r.leftover_volume_mm3 = leftover.volume_mm3;
  r.leftover_max_mm = leftover.max_thickness_mm;
  r.region_count = static_cast<int>(leftover.regions.size());
  r.regions = std::move(leftover.regions);
  if (static_cast<int>(r.regions.size()) > max_listed) r.regions.resize(max_listed);
  r.face_count = static_cast<int>(leftover.faces.size());
  r.faces = std::move(leftover.faces);
  std::stable_sort(r.faces.begin(), r.faces.end(), [](const FaceCusp& a, const FaceCusp& b) { return a.max_mm > b.max_mm; });
  if (static_cast<int>(r.faces.size()) > max_listed) r.faces.resize(max_listed);
}

// What VerifyOptions::keep_sweeping is shown: the findings of the rows swept so far, counted as the report counts them.
VerificationReport findingsSoFar(const SweepResult& sweep, const Toolpath& path, const VerifyOptions& options,
                                 const std::vector<int>& triangle_face, const PartDistance& distance) {
  VerificationReport so_far;
  so_far.tolerance_mm = options.tolerance;
  listFindings(so_far, sweep.findings, path, options.tolerance, options.face_allowance, triangle_face, distance,
               options.max_listed);
  return so_far;
}

}  // namespace

double automaticResolution(const Box& box) {
  const Vec3 s = box.size();
  const double area = s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
  return std::max(kFinestAutomatic, std::sqrt(area / kAutomaticRays));
}

VerificationReport verifyToolpath(const Mesh& part_mesh, const std::vector<int>& part_faces, const Toolpath& path,
                                  const std::vector<Tool>& tools, const VerifyOptions& options,
                                  VerificationState* state, const ProgressSink& progress,
                                  const std::vector<SweepCheckpoint>& resume_from) {
  const auto start = std::chrono::steady_clock::now();
  VerificationReport r;
  if (path.empty()) throw InputError("verify: the toolpath has no points");
  if (part_mesh.triangles.empty()) throw InputError("verify: the part has no triangles");
  // An open mesh bounds no solid: the part is its closure (solid_closure.h), as the roughing plans against.
  SolidClosure closure = closeOpenMesh(part_mesh);
  const Mesh& part = closure.mesh;
  std::vector<int> triangle_face = part_faces;
  triangle_face.resize(part.triangles.size(), -1);
  if (!(options.tolerance >= 0.0)) throw InputError("verify: the tolerance must not be negative");
  const Box part_box = boundingBox(part);
  const Box box = options.stock_mesh ? unite(boundingBox(*options.stock_mesh), part_box)
                                     : stockBox(part_box, std::max(options.stock_margin, 0.0));
  const double resolution = options.resolution > 0.0 ? options.resolution : automaticResolution(box);
  if (!reportProgress(progress, "verification", 0, "the part and the stock on a lattice of " +
                                                       std::to_string(resolution) + " mm")) {
    r.cancelled = true;
    return r;
  }
  const DexelLattice lattice = DexelLattice::over(box, resolution);
  const std::map<std::string, ToolSolid> solids = toolSolids(tools, options.tool_chord_mm);
  MeshDexels part_dexels(part, lattice);
  Stock stock = initialStock(options.stock_mesh, lattice, part_dexels);

  r.resolution_mm = resolution;
  r.closed_open_mesh_edges = closure.boundary_edges;
  r.tolerance_mm = options.tolerance;
  r.spacing = lattice.spacing;
  r.dexels = lattice.totalRays();
  r.moves = static_cast<int>(path.size());
  r.stock_box = box;
  r.stock_volume_mm3 = stock.volume();
  r.part_volume_mm3 = part_dexels.volume();

  const PartDistance distance(part);
  SweepOptions sweep_options;
  sweep_options.tolerance = options.tolerance;
  sweep_options.step_fraction = options.step_fraction;
  sweep_options.cusp_step = options.cusp_step;
  sweep_options.threads = options.threads;
  ProgressSink sweeping;  // the sweep's share of the moves, within the stage
  if (progress)
    sweeping = [&progress](const ProgressReport& p) {
      return reportProgress(progress, p.stage, kSweepStart + (kSweepEnd - kSweepStart) * p.fraction, p.message, p.done);
    };
  const std::uint64_t inputs = sweep_checkpoints::inputsKey(lattice, part, options.stock_mesh, options);
  SweepResult sweep;
  const int resume = sweep_checkpoints::resumable(resume_from, path, inputs, tools);
  if (resume >= 0) {
    const SweepCheckpoint& c = resume_from[resume];
    stock = c.stock;
    sweep.findings = c.findings;
    sweep.by_op = c.by_op;
    sweep.poses = c.poses;
    r.resumed_at_row = c.row;
  }
  // Swept piece by piece from one checkpoint row to the next, a copy of the stock kept at each (handed to `state` at
  // the end: `resume_from` may be a state's own).
  std::vector<SweepCheckpoint> kept;
  std::vector<int> ends = sweep_checkpoints::checkpointRows(path, std::max(options.checkpoints, 0));
  ends.erase(ends.begin(), std::upper_bound(ends.begin(), ends.end(), r.resumed_at_row));
  const std::vector<std::uint64_t> keys = sweep_checkpoints::prefixKeys(path, ends, inputs, tools);
  ends.push_back(static_cast<int>(path.size()));
  for (std::size_t k = 0; k < ends.size() && !sweep.cancelled; ++k) {
    sweep_options.first_row = k == 0 ? r.resumed_at_row : ends[k - 1];
    sweep_options.end_row = ends[k];
    sweep_checkpoints::addSweep(sweep, sweepToolpath(stock, part_dexels, distance, path, solids, sweep_options,
                                                     sweeping));
    if (k + 1 == ends.size() || sweep.cancelled) continue;
    if (state) kept.push_back({ends[k], keys[k], stock, sweep.findings, sweep.by_op, sweep.poses});
    if (options.keep_sweeping &&
        !options.keep_sweeping(ends[k], findingsSoFar(sweep, path, options, triangle_face, distance))) {
      r.stopped_at_row = ends[k];
      break;
    }
  }
  const bool stopped = r.stopped_at_row > 0;
  r.cancelled = sweep.cancelled || (!stopped && !reportProgress(progress, "verification", kSweepEnd,
                                                                "measuring what is left of the stock"));
  r.poses = sweep.poses;
  for (const CutterLocation& row : path) r.by_op[row.op];
  for (const auto& [op, swept] : sweep.by_op) r.by_op[op].swept = swept;
  r.seconds_sweep = sweep.seconds;
  r.moves_per_second = (r.moves - r.resumed_at_row) / std::max(sweep.seconds, 1e-9);
  listFindings(r, sweep.findings, path, options.tolerance, options.face_allowance, triangle_face, distance,
               options.max_listed);

  r.remaining_volume_mm3 = stock.volume();
  r.removed_volume_mm3 = r.stock_volume_mm3 - r.remaining_volume_mm3;
  if (r.cancelled || stopped) {
    if (state) state->checkpoints = std::move(kept);
    r.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  }
  LeftoverAnalysis leftover = analyseLeftover(stock, part_dexels, part_box, triangle_face);
  if (!part_faces.empty())
    r.face_checks = checkFaces(leftover, sweep.findings, triangle_face, distance, options.tolerance,
                               options.face_allowance);
  listLeftover(r, std::move(leftover), options.max_listed);
  if (state) {
    state->checkpoints = std::move(kept);
    state->stock = std::move(stock);
    state->part = std::move(part_dexels);
  }
  r.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  reportProgress(progress, "verification", 1.0, "verification done");
  return r;
}

}  // namespace art2part
