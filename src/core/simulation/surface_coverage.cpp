#include "art2part/simulation/surface_coverage.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <thread>

#include "art2part/common/parallel.h"
#include "feed_moves.h"

namespace art2part {

using namespace simulation_detail;

namespace {

constexpr double kAutomaticSamples = 4e5;  // the header's "about 400k samples"
constexpr double kFinestSpacing = 0.2, kCoarsestSpacing = 2.0;  // mm: the automatic spacing's bounds
constexpr double kMaxCells = 4e6;          // grid cells at most (4 bytes of start and count each)
constexpr double kCellsPerSpacing = 2.0;   // a cell holds a few samples: 2 spacings wide
constexpr double kChunkTravelMin = 1.0;    // mm: a chunk holds a flute radius of travel, at least this much
constexpr int kSlabCells = 2;              // cells per slab of x handed out to the threads in turn
// Pieces at most 4 spacings long: a sliver's samples no farther apart along it (2 would give 6.2 M samples on CTC-02's
// fine mesh instead of 2.5 M, no edge bound 1.0 M with samples up to a sliver's length apart).
constexpr double kEdgeFactor = 4;

struct Sample {
  Vec3 point;
  double area;
  int face;
};

// Longest-edge bisection until each piece is small enough; a sample at each piece's centroid.
void spreadSamples(const Vec3& a, const Vec3& b, const Vec3& c, double max_area, double max_edge, int face,
                   std::vector<Sample>& out) {
  const double area = 0.5 * (b - a).cross(c - a).norm();
  const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(), ca = (a - c).squaredNorm();
  const double longest = std::max({ab, bc, ca});
  if (area <= max_area && longest <= max_edge * max_edge) {
    out.push_back({(a + b + c) / 3.0, area, face});
    return;
  }
  if (longest == ab) {
    const Vec3 m = 0.5 * (a + b);
    spreadSamples(a, m, c, max_area, max_edge, face, out);
    spreadSamples(m, b, c, max_area, max_edge, face, out);
  } else if (longest == bc) {
    const Vec3 m = 0.5 * (b + c);
    spreadSamples(a, b, m, max_area, max_edge, face, out);
    spreadSamples(a, m, c, max_area, max_edge, face, out);
  } else {
    const Vec3 m = 0.5 * (c + a);
    spreadSamples(a, b, m, max_area, max_edge, face, out);
    spreadSamples(m, b, c, max_area, max_edge, face, out);
  }
}

// Samples bucketed in a uniform grid; each cell's samples are order[start[cell] .. start[cell] + live[cell]) while
// uncovered (a covered sample is swapped behind the live ones).
struct SampleGrid {
  Box box;
  double cell = 1;
  std::array<int, 3> cells{1, 1, 1};
  std::vector<int> start, live, order;
  // The cells holding samples, by column (ix, iy): their iz, ascending, at column_iz[column_start[c] ..].
  std::vector<int> column_start, column_iz;

  int index(int ix, int iy, int iz) const { return ix + cells[0] * (iy + cells[1] * iz); }
  int coordinate(int axis, double x) const {
    return std::clamp(static_cast<int>(std::floor((x - box.min[axis]) / cell)), 0, cells[axis] - 1);
  }
};

SampleGrid gridOf(const std::vector<Sample>& samples, double spacing) {
  SampleGrid g;
  for (const Sample& s : samples) g.box.extend(s.point);
  const Vec3 size = g.box.size() + Vec3::Constant(1e-6);
  g.cell = std::max(kCellsPerSpacing * spacing, std::cbrt(size.prod() / kMaxCells));
  auto fit = [&g, &size]() {
    for (int a = 0; a < 3; ++a) g.cells[a] = std::max(1, static_cast<int>(std::ceil(size[a] / g.cell)));
    return static_cast<double>(g.cells[0]) * g.cells[1] * g.cells[2];
  };
  while (fit() > kMaxCells) g.cell *= 1.25;  // a flat box: its thin side counts one cell, not its share
  const int count = g.cells[0] * g.cells[1] * g.cells[2];
  std::vector<int> cell_of(samples.size());
  g.start.assign(count + 1, 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3& p = samples[i].point;
    cell_of[i] = g.index(g.coordinate(0, p.x()), g.coordinate(1, p.y()), g.coordinate(2, p.z()));
    ++g.start[cell_of[i] + 1];
  }
  for (int c = 0; c < count; ++c) g.start[c + 1] += g.start[c];
  g.live.resize(count);
  for (int c = 0; c < count; ++c) g.live[c] = g.start[c + 1] - g.start[c];
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  g.order.resize(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) g.order[fill[cell_of[i]]++] = static_cast<int>(i);
  const int columns = g.cells[0] * g.cells[1];
  g.column_start.assign(columns + 1, 0);
  for (int c = 0; c < count; ++c)
    if (g.live[c] > 0) ++g.column_start[c % columns + 1];
  for (int c = 0; c < columns; ++c) g.column_start[c + 1] += g.column_start[c];
  g.column_iz.resize(g.column_start[columns]);
  std::vector<int> next(g.column_start.begin(), g.column_start.end() - 1);
  for (int c = 0; c < count; ++c)  // ascending c: ascending iz within a column
    if (g.live[c] > 0) g.column_iz[next[c % columns]++] = c / columns;
  return g;
}

// Poses k0..k1 (of 0..steps) of one feed move.
struct MoveStretch {
  int move, steps, k0, k1;
};

// About a flute radius of travel (at least a millimetre) of consecutive feed moves of one tool, with its box.
struct Chunk {
  int tool = 0;
  std::vector<MoveStretch> stretches;
  Box box;
};

void extendBox(Box& box, const Box& by) {
  box.extend(by.min);
  box.extend(by.max);
}

std::vector<Chunk> chunksOf(const std::vector<FeedMove>& moves, const std::vector<Flutes>& flutes, double step,
                            double tolerance, long long& poses) {
  std::vector<Chunk> chunks;
  Chunk current;
  double travel = 0;
  auto close = [&]() {
    if (!current.stretches.empty()) chunks.push_back(std::move(current));
    current = Chunk();
    travel = 0;
  };
  for (int m = 0; m < static_cast<int>(moves.size()); ++m) {
    const FeedMove& move = moves[m];
    const Flutes& f = flutes[move.tool];
    if (f.pieces.empty()) continue;
    if (!current.stretches.empty() && current.tool != move.tool) close();
    const double length = std::max(f.radius, kChunkTravelMin);
    const int steps = poseSteps(move, f, step);
    poses += steps + 1;
    const double per_step = std::max((move.to.tip - move.from.tip).norm() + move.angle * f.h_max, 1e-12) / steps;
    int k = 0;
    while (k <= steps) {
      const int room = std::max(1, static_cast<int>((length - travel) / per_step));
      const int k1 = std::min(steps, k + room);
      current.tool = move.tool;
      current.stretches.push_back({m, steps, k, k1});
      if (move.angle < 1e-9) {
        extendBox(current.box, flutesBox(f, poseAt(move, static_cast<double>(k) / steps), tolerance));
        extendBox(current.box, flutesBox(f, poseAt(move, static_cast<double>(k1) / steps), tolerance));
      } else {
        for (int j = k; j <= k1; ++j)
          extendBox(current.box, flutesBox(f, poseAt(move, static_cast<double>(j) / steps), tolerance));
      }
      travel += (k1 - k) * per_step;
      if (travel >= length) close();
      k = k1 + 1;
    }
  }
  close();
  return chunks;
}

// [lo, hi] where q(k) = a k^2 + b k + c <= 0, intersected with [lo, hi]; false when empty.
bool quadraticBelowZero(double a, double b, double c, double& lo, double& hi) {
  if (a == 0) {
    if (b == 0) return c <= 0;
    const double root = -c / b;
    if (b > 0) hi = std::min(hi, root);
    else lo = std::max(lo, root);
    return lo <= hi;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return a < 0;  // a > 0 here in practice (a squared norm); a < 0 would be everywhere
  const double root = std::sqrt(disc);
  const double q = -0.5 * (b + std::copysign(root, b));
  double r1 = q / a, r2 = q != 0 ? c / q : r1;
  if (r1 > r2) std::swap(r1, r2);
  lo = std::max(lo, r1);
  hi = std::min(hi, r2);
  return lo <= hi;
}

// One thread's share: the samples of the cells in its slabs.
class Worker {
 public:
  Worker(const std::vector<Sample>& samples, SampleGrid& grid, std::vector<char>& covered,
         const std::vector<FeedMove>& moves, const std::vector<Flutes>& flutes, double tolerance, int thread,
         int threads)
      : samples_(samples), grid_(grid), covered_(covered), moves_(moves), flutes_(flutes), tolerance_(tolerance),
        thread_(thread), threads_(threads) {}

  void run(const std::vector<Chunk>& chunks) {
    for (const Chunk& chunk : chunks) visit(chunk);
  }
  long long queries() const { return queries_; }

 private:
  bool owns(int ix) const { return (ix / kSlabCells) % threads_ == thread_; }

  void visit(const Chunk& chunk) {
    const Box& b = chunk.box;
    if ((b.max.array() < grid_.box.min.array()).any() || (b.min.array() > grid_.box.max.array()).any()) return;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = grid_.coordinate(a, b.min[a]);
      hi[a] = grid_.coordinate(a, b.max[a]);
    }
    const int columns = grid_.cells[0] * grid_.cells[1];
    for (int iy = lo[1]; iy <= hi[1]; ++iy)
      for (int ix = lo[0]; ix <= hi[0]; ++ix) {
        if (!owns(ix)) continue;
        const int column = grid_.index(ix, iy, 0);
        const auto first = grid_.column_iz.begin() + grid_.column_start[column];
        const auto last = grid_.column_iz.begin() + grid_.column_start[column + 1];
        for (auto iz = std::lower_bound(first, last, lo[2]); iz != last && *iz <= hi[2]; ++iz)
          visitCell(chunk, column + columns * *iz);
      }
  }

  void visitCell(const Chunk& chunk, int cell) {
    int& live = grid_.live[cell];
    const int first = grid_.start[cell];
    for (int j = 0; j < live;) {
      const int s = grid_.order[first + j];
      if (coveredBy(chunk, samples_[s].point)) {
        covered_[s] = 1;
        std::swap(grid_.order[first + j], grid_.order[first + live - 1]);
        --live;
      } else {
        ++j;
      }
    }
  }

  double distance(const Flutes& f, const ToolPose& pose, const Vec3& p) {
    ++queries_;
    const Vec3 w = p - pose.tip;
    const double h = w.dot(pose.axis);
    return f.distance(h, std::sqrt(std::max(0.0, w.squaredNorm() - h * h)));
  }

  bool within(const Flutes& f, const ToolPose& pose, const Vec3& p) {
    const Vec3 w = p - pose.tip;
    const double h = w.dot(pose.axis);
    if (h < f.h_min - tolerance_ || h > f.h_max + tolerance_) return false;
    if (w.squaredNorm() - h * h > (f.radius + tolerance_) * (f.radius + tolerance_)) return false;
    return distance(f, pose, p) <= tolerance_;
  }

  // The least distance over poses k_first..k_last of a straight move, found by bisecting the convex distance's
  // forward difference; true when it is within the tolerance.
  bool nearestWithin(const Flutes& f, const Vec3& tip, const Vec3& delta, const Vec3& axis, int lo, int hi,
                     const Vec3& p) {
    while (lo < hi) {
      const int mid = lo + (hi - lo) / 2;
      const double here = distance(f, {tip + mid * delta, axis}, p);
      if (here <= tolerance_) return true;
      if (distance(f, {tip + (mid + 1) * delta, axis}, p) < here) lo = mid + 1;
      else hi = mid;
    }
    return distance(f, {tip + lo * delta, axis}, p) <= tolerance_;
  }

  bool coveredBy(const Chunk& chunk, const Vec3& p) {
    const Flutes& f = flutes_[chunk.tool];
    const double reach = f.radius + tolerance_;
    for (const MoveStretch& st : chunk.stretches) {
      const FeedMove& move = moves_[st.move];
      if (move.angle >= 1e-9) {
        for (int k = st.k0; k <= st.k1; ++k)
          if (within(f, poseAt(move, static_cast<double>(k) / st.steps), p)) return true;
        continue;
      }
      // A straight move: the poses whose bounding cylinder holds p, solved for k.
      const Vec3& a = move.from.axis;
      const Vec3 delta = (move.to.tip - move.from.tip) / st.steps;
      const Vec3 w0 = p - move.from.tip;
      const double h0 = w0.dot(a), da = delta.dot(a);
      double lo = st.k0, hi = st.k1;
      // Slab: h0 - k da within [h_min - tol, h_max + tol].
      if (!quadraticBelowZero(0, da, (f.h_min - tolerance_) - h0, lo, hi)) continue;  // h0 - k da >= h_min - tol
      if (!quadraticBelowZero(0, -da, h0 - (f.h_max + tolerance_), lo, hi)) continue;
      // Radius: |w0 - k delta|^2 - (h0 - k da)^2 <= reach^2.
      // Along the axis only (qa ~ 0): rho does not change, qb is 0 too.
      const bool along_axis = delta.squaredNorm() - da * da <= 1e-9 * delta.squaredNorm();
      const double qa = along_axis ? 0.0 : delta.squaredNorm() - da * da;
      const double qb = along_axis ? 0.0 : -2 * (w0.dot(delta) - h0 * da);
      const double qc = w0.squaredNorm() - h0 * h0 - reach * reach;
      if (!quadraticBelowZero(qa, qb, qc, lo, hi)) continue;
      const int k_first = std::max(st.k0, static_cast<int>(std::ceil(lo - 1e-9)));
      const int k_last = std::min(st.k1, static_cast<int>(std::floor(hi + 1e-9)));
      if (k_first > k_last) continue;
      if (f.convex) {
        if (nearestWithin(f, move.from.tip, delta, a, k_first, k_last, p)) return true;
        continue;
      }
      for (int k = k_first; k <= k_last; ++k)
        if (within(f, {move.from.tip + k * delta, a}, p)) return true;
    }
    return false;
  }

  const std::vector<Sample>& samples_;
  SampleGrid& grid_;
  std::vector<char>& covered_;
  const std::vector<FeedMove>& moves_;
  const std::vector<Flutes>& flutes_;
  double tolerance_;
  int thread_, threads_;
  long long queries_ = 0;
};

void checkOptions(const CoverageOptions& o) {
  if (!(o.tolerance >= 0)) throw InputError("surfaceCoverage: the tolerance must not be negative");
  if (!(o.pose_step > 0)) throw InputError("surfaceCoverage: the pose step must be positive");
  if (!(o.sample_spacing >= 0)) throw InputError("surfaceCoverage: the sample spacing must not be negative");
}

int faceOf(const std::vector<int>& triangle_face, const std::vector<Face>& faces, int t) {
  const int face = t < static_cast<int>(triangle_face.size()) ? triangle_face[t] : -1;
  if (face >= static_cast<int>(faces.size()))
    throw InputError("surfaceCoverage: triangle " + std::to_string(t) + " has face " + std::to_string(face) +
                     " but there are " + std::to_string(faces.size()) + " faces");
  return face < 0 ? -1 : face;
}

}  // namespace

CoverageReport surfaceCoverage(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<Face>& faces,
                               const Toolpath& path, const std::vector<Tool>& tools, const CoverageOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  checkOptions(options);
  const std::vector<FeedMove> moves = feedMoves(path, tools, "surfaceCoverage");
  const std::vector<Flutes> flutes = flutesOf(tools);

  CoverageReport r;
  const double area = surfaceArea(mesh);
  r.sample_spacing_mm = options.sample_spacing > 0
                            ? options.sample_spacing
                            : std::clamp(std::sqrt(area / kAutomaticSamples), kFinestSpacing, kCoarsestSpacing);
  std::vector<Sample> samples;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    spreadSamples(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2), r.sample_spacing_mm * r.sample_spacing_mm,
                  kEdgeFactor * r.sample_spacing_mm, faceOf(triangle_face, faces, t), samples);
  r.samples = static_cast<long>(samples.size());

  std::vector<char> covered(samples.size(), 0);
  if (!samples.empty()) {
    SampleGrid grid = gridOf(samples, r.sample_spacing_mm);
    const std::vector<Chunk> chunks = chunksOf(moves, flutes, options.pose_step, options.tolerance, r.poses);
    const int threads = std::max(1, options.threads > 0 ? options.threads
                                                        : static_cast<int>(std::thread::hardware_concurrency()));
    std::vector<Worker> workers;
    for (int t = 0; t < threads; ++t)
      workers.emplace_back(samples, grid, covered, moves, flutes, options.tolerance, t, threads);
    parallelFor(threads, threads, [&workers, &chunks](int t) { workers[t].run(chunks); });
    for (const Worker& w : workers) r.pose_queries += w.queries();
  }

  r.faces.resize(faces.size());
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) r.faces[f] = {f, faces[f].type};
  std::array<TypeCoverage, 6> by_type;
  std::array<bool, 6> present{};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    const double got = covered[i] ? s.area : 0.0;
    r.area_mm2 += s.area;
    r.covered_mm2 += got;
    const SurfaceType type = s.face >= 0 ? faces[s.face].type : SurfaceType::Other;
    const int ti = static_cast<int>(type);
    by_type[ti].type = type;
    by_type[ti].area_mm2 += s.area;
    by_type[ti].covered_mm2 += got;
    present[ti] = true;
    if (s.face >= 0) {
      FaceCoverage& fc = r.faces[s.face];
      fc.area_mm2 += s.area;
      fc.covered_mm2 += got;
      ++fc.samples;
      fc.covered_samples += covered[i];
    }
  }
  for (int ti = 0; ti < 6; ++ti)
    if (present[ti]) r.types.push_back(by_type[ti]);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace art2part
