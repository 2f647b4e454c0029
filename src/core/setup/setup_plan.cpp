// Setup planning (thesis 3.3): the visibility matrix as a minimum cover problem biased towards parallel and
// perpendicular access (3.3.2), solved, and turned into setups with frames and the faces and triangles they machine.
#include "art2part/setup/setup_plan.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>

#include "art2part/common/angles.h"

#include "setup_internal.h"

namespace art2part {
namespace setup_detail {
namespace {

double radians(double degrees) { return degrees * kPi / 180.0; }

// Square (3.3.2): the direction meets the face within `angle` of its normal (perpendicular access) or within `angle`
// of its plane (parallel access, the flank of the tool).
bool square(const Vec3& direction, const Vec3& normal, double cos_perpendicular, double sin_parallel) {
  const double c = direction.dot(normal);
  return c > cos_perpendicular || std::abs(c) < sin_parallel;
}

// Keeps only the directions of `cone` that meet the face square.
void keepSquare(Cone& cone, const std::vector<Vec3>& directions, const Vec3& normal, const SetupOptions& options) {
  const double cos_perpendicular = std::cos(radians(options.pp_angle_deg));
  const double sin_parallel = std::sin(radians(options.pp_angle_deg));
  for (int d = 0; d < static_cast<int>(directions.size()); ++d)
    if (coneHas(cone, d) && !square(directions[d], normal, cos_perpendicular, sin_parallel))
      cone[d >> 6] &= ~(std::uint64_t(1) << (d & 63));
}

}  // namespace

std::vector<SquareFace> squareFaces(const Part& part, const VisibilityResult& visibility,
                                    const std::vector<std::vector<int>>& face_triangles, const SetupOptions& options) {
  std::vector<SquareFace> out;
  if (!options.parallel_perpendicular) return out;
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    const Face& face = part.faces[f];
    if (face.type != SurfaceType::Plane || face.area <= 0.0 || face_triangles[f].empty() || face.normal.norm() < 0.5)
      continue;
    SquareFace s{f, commonCone(visibility.map, face_triangles[f])};
    keepSquare(s.earners, visibility.directions.directions, face.normal.normalized(), options);
    if (coneSize(s.earners) > 0) out.push_back(std::move(s));
  }
  return out;
}

void checkSetupInputs(const Part& part, const VisibilityResult& visibility, const SetupOptions& options) {
  const int T = part.mesh.triangleCount();
  if (visibility.map.triangles() != T)
    throw InputError("the visibility map has " + std::to_string(visibility.map.triangles()) +
                     " triangles but the part has " + std::to_string(T) + ": it belongs to another mesh");
  if (visibility.map.directions() != visibility.directions.size())
    throw InputError("the visibility map has " + std::to_string(visibility.map.directions()) +
                     " directions but the direction set " + std::to_string(visibility.directions.size()));
  if (static_cast<int>(part.triangle_face.size()) != T)
    throw InputError("the part's triangle to face map has " + std::to_string(part.triangle_face.size()) +
                     " entries for " + std::to_string(T) + " triangles");
  if (!(options.max_tilt_deg > 0.0 && options.max_tilt_deg <= 180.0))
    throw InputError("the 5-axis tilt must be in (0, 180] degrees, not " + std::to_string(options.max_tilt_deg));
  if (!(options.pp_angle_deg > 0.0 && options.pp_angle_deg < 45.0))
    throw InputError("the parallel-perpendicular angle must be in (0, 45) degrees, not " +
                     std::to_string(options.pp_angle_deg));
  if (!(options.time_limit_s >= 0.0))
    throw InputError("the cover time limit must be at least 0 s, not " + std::to_string(options.time_limit_s));
}

// The cover problem over a reach matrix (moved in) and the square faces as bonus items.
CoverProblem coverProblemOf(BitMatrix reach, const std::vector<SquareFace>& square_faces, const Part& part) {
  CoverProblem p;
  p.candidates = reach.columns();
  p.earners = BitMatrix(static_cast<int>(square_faces.size()), reach.columns());
  for (int i = 0; i < static_cast<int>(square_faces.size()); ++i) {
    std::copy(square_faces[i].earners.begin(), square_faces[i].earners.end(), p.earners.row(i));
    p.bonus_weight.push_back(part.faces[square_faces[i].face].area);
  }
  p.coverers = std::move(reach);
  return p;
}

}  // namespace setup_detail

using namespace setup_detail;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int columnCount(const BitMatrix& m, int column) {
  int n = 0;
  for (int r = 0; r < m.rows(); ++r) n += m.get(r, column);
  return n;
}

double squareFaceArea(const Part& part, const std::vector<SquareFace>& square_faces, int direction) {
  double area = 0.0;
  for (const SquareFace& s : square_faces)
    if (coneHas(s.earners, direction)) area += part.faces[s.face].area;
  return area;
}

double assignedArea(const Mesh& mesh, const Setup& setup) {
  double area = 0.0;
  for (int t : setup.triangles) area += triangleArea(mesh, t);
  return area;
}

// Most assigned area first; ties by direction index so the order does not depend on the solver.
void sortByAssignedArea(const Mesh& mesh, std::vector<Setup>& setups) {
  std::vector<std::pair<double, Setup>> keyed;
  for (Setup& s : setups) keyed.emplace_back(assignedArea(mesh, s), std::move(s));
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second.direction < b.second.direction;
  });
  setups.clear();
  for (auto& k : keyed) setups.push_back(std::move(k.second));
}

std::vector<int> facesOf(const Part& part, const std::vector<int>& triangles) {
  std::vector<int> faces;
  for (int t : triangles)
    if (part.triangle_face[t] >= 0 && part.triangle_face[t] < static_cast<int>(part.faces.size()))
      faces.push_back(part.triangle_face[t]);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

// Setups from the chosen directions and the assignment, with frames.
std::vector<Setup> buildSetups(const Part& part, const DirectionSet& directions, const CoverProblem& problem,
                               const std::vector<int>& chosen, const std::vector<SquareFace>& square_faces,
                               Assignment assignment) {
  std::vector<Setup> setups;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    Setup s;
    s.direction = chosen[k];
    s.special = s.direction < static_cast<int>(directions.special.size()) && directions.special[s.direction] != 0;
    s.frame = setupFrame(part, directions.directions[s.direction]);
    s.faces = std::move(assignment.faces[k]);
    s.triangles = std::move(assignment.triangles[k]);
    s.reachable_triangles = columnCount(problem.coverers, s.direction);
    s.square_face_area = squareFaceArea(part, square_faces, s.direction);
    setups.push_back(std::move(s));
  }
  sortByAssignedArea(part.mesh, setups);
  return setups;
}

// The stage's reports: at each step, and during the cover search at most every kSetupReportSeconds (the search asks
// every few nodes), the fraction the share of the time limit spent. Once the sink says stop, it stays stopped.
class SetupProgress {
 public:
  static constexpr double kCoverStart = 0.1, kCoverEnd = 0.9;  // the search's part of the stage

  SetupProgress(const ProgressSink& sink, double time_limit_s) : sink_(sink), time_limit_s_(time_limit_s) {}

  bool step(double fraction, const std::string& message) {
    last_ = std::chrono::steady_clock::now();
    fraction_ = std::max(fraction_, fraction);
    if (!stopped_) stopped_ = !reportProgress(sink_, "setups", fraction_, message);
    return !stopped_;
  }

  void startSearch() { search_start_ = std::chrono::steady_clock::now(); }

  // Asked by the search every few nodes.
  bool searching() {
    if (stopped_ || !sink_) return !stopped_;
    if (secondsSince(last_) < kSetupReportSeconds) return true;
    const double spent = secondsSince(search_start_);
    const double share = time_limit_s_ > 0 && std::isfinite(time_limit_s_) ? std::min(1.0, spent / time_limit_s_) : 0;
    return step(kCoverStart + share * (kCoverEnd - kCoverStart),
                "minimum cover: searching the cyclic core, " + std::to_string(static_cast<int>(spent)) +
                    " s of at most " + std::to_string(static_cast<int>(std::ceil(time_limit_s_))) + " s");
  }

 private:
  const ProgressSink& sink_;
  double time_limit_s_;
  std::chrono::steady_clock::time_point last_, search_start_;
  double fraction_ = 0;
  bool stopped_ = false;
};

}  // namespace

MachineMode parseMachineMode(const std::string& text) {
  if (text == "3axis") return MachineMode::ThreeAxis;
  if (text == "5axis") return MachineMode::FiveAxis;
  throw InputError("unknown machine mode '" + text + "' (use 3axis or 5axis)");
}

const char* machineModeName(MachineMode mode) { return mode == MachineMode::ThreeAxis ? "3axis" : "5axis"; }

CoverProblem setupCoverProblem(const Part& part, const VisibilityResult& visibility, const BitMatrix& reach,
                               const SetupOptions& options) {
  checkSetupInputs(part, visibility, options);
  if (reach.rows() != visibility.map.triangles() || reach.columns() != visibility.map.directions())
    throw InputError("the reach matrix is " + std::to_string(reach.rows()) + " x " + std::to_string(reach.columns()) +
                     ", the visibility map " + std::to_string(visibility.map.triangles()) + " x " +
                     std::to_string(visibility.map.directions()));
  return coverProblemOf(reach, squareFaces(part, visibility, faceTriangles(part), options), part);
}

SetupPlan planSetups(const Part& part, const VisibilityResult& visibility, const SetupOptions& options,
                     const ProgressSink& progress) {
  checkSetupInputs(part, visibility, options);
  SetupPlan plan;
  plan.mode = options.mode;
  plan.max_tilt_deg = options.mode == MachineMode::FiveAxis ? options.max_tilt_deg : 0.0;
  SetupProgress reports(progress, options.time_limit_s);
  const auto stop = [&plan] {
    plan.cancelled = true;
    return plan;
  };

  if (!reports.step(0, "what each direction reaches")) return stop();
  auto start = std::chrono::steady_clock::now();
  BitMatrix reach = reachMatrix(visibility, options);
  plan.seconds_reach = secondsSince(start);

  if (!reports.step(0.05, "the cover problem: reach and square faces")) return stop();
  start = std::chrono::steady_clock::now();
  const std::vector<std::vector<int>> face_triangles = faceTriangles(part);
  const std::vector<SquareFace> square_faces = squareFaces(part, visibility, face_triangles, options);
  const CoverProblem problem = coverProblemOf(std::move(reach), square_faces, part);
  if (!reports.step(SetupProgress::kCoverStart, "minimum cover: reduction to the cyclic core")) return stop();
  reports.startSearch();
  std::function<bool()> keep_going;  // none without a sink: the search runs as it always did
  if (progress) keep_going = [&reports] { return reports.searching(); };
  CoverResult cover = chooseSetups(problem, visibility.directions.special, options, keep_going);
  plan.seconds_cover = secondsSince(start);
  if (cover.stopped || !reports.step(SetupProgress::kCoverEnd, "assigning faces and triangles to the setups"))
    return stop();
  plan.proven_minimal = cover.proven_minimal;
  plan.bonus_proven_best = cover.bonus_proven_best;
  plan.cover = cover.stats;
  plan.greedy_setups = static_cast<int>(greedyCover(problem).chosen.size());

  start = std::chrono::steady_clock::now();
  Assignment assignment = assignToSetups(part, face_triangles, problem.coverers, visibility.directions.directions,
                                         cover.chosen, square_faces);
  plan.split_faces = std::move(assignment.split_faces);
  plan.setups = buildSetups(part, visibility.directions, problem, cover.chosen, square_faces, std::move(assignment));
  plan.unmachinable_triangles = std::move(cover.uncoverable);
  std::sort(plan.unmachinable_triangles.begin(), plan.unmachinable_triangles.end());
  plan.unmachinable_faces = facesOf(part, plan.unmachinable_triangles);
  plan.seconds_assign = secondsSince(start);
  reports.step(1.0, "setups done");
  return plan;
}

}  // namespace art2part
