#include "art2part/simulation/scallop_probe.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include "art2part/common/angles.h"
#include "art2part/common/parallel.h"

#include "feed_moves.h"

namespace art2part {

using namespace simulation_detail;

namespace {

constexpr int kMoveBlock = 64;  // consecutive moves under one box: a path is coherent, so whole blocks are skipped

struct Block {
  Box box;
  int first = 0, last = 0;  // moves [first, last)
};

bool overlaps(const Box& a, const Box& b) {
  return !((a.max.array() < b.min.array()).any() || (b.max.array() < a.min.array()).any());
}

// The window's frame: rows x, y, z (z the normal), origin at the sample.
struct Frame {
  Eigen::Matrix3d rows;
  Vec3 origin;
  Vec3 point(const Vec3& p) const { return rows * (p - origin); }
  Vec3 direction(const Vec3& d) const { return rows * d; }
};

// `turn` (rad) about the normal: the lattice's rows at a random angle, so that a ridge along a row of the tangent
// basis does not hide its apex between two rows.
Frame frameAt(const Vec3& point, const Vec3& normal, double turn) {
  const Vec3 x0 = normal.unitOrthogonal(), y0 = normal.cross(x0);
  const Vec3 x = std::cos(turn) * x0 + std::sin(turn) * y0, y = normal.cross(x);
  Frame f;
  f.rows.row(0) = x.transpose();
  f.rows.row(1) = y.transpose();
  f.rows.row(2) = normal.transpose();
  f.origin = point;
  return f;
}

// A square lattice of n x n rays at `pitch` in the window's plane, the first at (first_u, first_v).
struct RayGrid {
  int n = 0;
  double first_u = 0, first_v = 0, pitch = 0;
  double u(int i) const { return first_u + i * pitch; }
  double v(int j) const { return first_v + j * pitch; }
  // Indices of the rays within [lo, hi] along u (or v); first > last when none.
  void range(double first, double lo, double hi, int& i0, int& i1) const {
    i0 = std::max(0, static_cast<int>(std::ceil((lo - first) / pitch - 1e-9)));
    i1 = std::min(n - 1, static_cast<int>(std::floor((hi - first) / pitch + 1e-9)));
  }
};

// A triangle in the window's frame.
struct LocalTriangle {
  Vec3 a, b, c;
};

class Prober {
 public:
  Prober(const Mesh& mesh, const std::vector<FeedMove>& moves, const std::vector<Flutes>& flutes,
         const std::vector<Box>& move_boxes, const std::vector<Block>& blocks, const ScallopProbeOptions& options)
      : mesh_(mesh), moves_(moves), flutes_(flutes), move_boxes_(move_boxes), blocks_(blocks), options_(options) {
    radius_ = std::hypot(std::sqrt(2.0) * options.half_width, options.depth);
  }

  void measure(ScallopWindow& window) {
    const Frame frame = frameAt(window.point, window.normal, window.turn);
    Box box;
    box.extend(window.point - Vec3::Constant(radius_));
    box.extend(window.point + Vec3::Constant(radius_));
    gatherTriangles(frame, box);
    gatherMoves(frame, box);
    RayGrid grid;
    grid.pitch = options_.pitch;
    grid.n = static_cast<int>(std::floor(2 * options_.half_width / options_.pitch + 1e-9)) + 1;
    grid.first_u = grid.first_v = -0.5 * (grid.n - 1) * options_.pitch;
    cast(frame, grid);
    double sum = 0;
    int best = -1;
    for (int r = 0; r < grid.n * grid.n; ++r) {
      if (!faces_up_[r]) continue;
      ++window.rays;
      if (lowest_[r] > surface_[r] + options_.depth) continue;
      ++window.reached;
      const double left = lowest_[r] - surface_[r];
      if (left >= 0) {
        sum += left;
        if (left > window.max_mm || best < 0) best = r;
        window.max_mm = std::max(window.max_mm, left);
      } else {
        window.deepest_cut_mm = std::max(window.deepest_cut_mm, -left);
      }
    }
    window.mean_mm = window.reached > 0 ? sum / window.reached : 0.0;
    if (best >= 0) refineMaximum(frame, grid.u(best % grid.n), grid.v(best / grid.n), window);
  }

  long long tests() const { return tests_; }

 private:
  static constexpr double kNone = 1e300;
  static constexpr int kRefineRays = 9;    // rays across each refinement lattice
  static constexpr int kRefineRounds = 2;  // each 4 times finer: the apex within pitch / 32 of some ray

  // The highest ray is the one nearest a ridge's apex line, which passes within a pitch of it: lattices 4 and 16 times
  // finer around it find the apex (the window's max only; the counts and the mean stay the lattice's).
  void refineMaximum(const Frame& frame, double u, double v, ScallopWindow& window) {
    double span = options_.pitch;
    for (int round = 0; round < kRefineRounds; ++round) {
      RayGrid fine;
      fine.n = kRefineRays;
      fine.pitch = 2 * span / (kRefineRays - 1);
      fine.first_u = u - span;
      fine.first_v = v - span;
      cast(frame, fine);
      for (int r = 0; r < fine.n * fine.n; ++r) {
        if (!faces_up_[r] || lowest_[r] > surface_[r] + options_.depth) continue;
        const double left = lowest_[r] - surface_[r];
        if (left > window.max_mm) {
          window.max_mm = left;
          u = fine.u(r % fine.n);
          v = fine.v(r / fine.n);
        }
      }
      span = fine.pitch;
    }
  }

  void gatherTriangles(const Frame& frame, const Box& box) {
    triangles_.clear();
    for (int t = 0; t < mesh_.triangleCount(); ++t) {
      const Vec3 &a = mesh_.corner(t, 0), &b = mesh_.corner(t, 1), &c = mesh_.corner(t, 2);
      if ((a.array() > box.max.array() && b.array() > box.max.array() && c.array() > box.max.array()).any() ||
          (a.array() < box.min.array() && b.array() < box.min.array() && c.array() < box.min.array()).any())
        continue;
      triangles_.push_back({frame.point(a), frame.point(b), frame.point(c)});
    }
  }

  // The moves whose box meets the window's, nearest the window first (so the rays come down early and the later,
  // farther poses are mostly skipped by the bound in lowerPiece).
  void gatherMoves(const Frame& frame, const Box& box) {
    near_moves_.clear();
    for (const Block& block : blocks_) {
      if (!overlaps(block.box, box)) continue;
      for (int m = block.first; m < block.last; ++m)
        if (overlaps(move_boxes_[m], box)) {
          const Vec3 &a = moves_[m].from.tip, &b = moves_[m].to.tip;
          const double l2 = (b - a).squaredNorm();
          const double f = l2 > 0 ? std::clamp((frame.origin - a).dot(b - a) / l2, 0.0, 1.0) : 0.0;
          near_moves_.push_back({(a + f * (b - a) - frame.origin).squaredNorm(), m});
        }
    }
    std::sort(near_moves_.begin(), near_moves_.end());
  }

  void cast(const Frame& frame, const RayGrid& grid) {
    const int rays = grid.n * grid.n;
    surface_.assign(rays, -kNone);
    faces_up_.assign(rays, 0);
    lowest_.assign(rays, kNone);
    for (const LocalTriangle& t : triangles_) crossTriangle(t, grid);
    // Rays no tool comes within the depth of stay "not reached": start each at that cap, so the bound holds.
    ceiling_ = -kNone;
    for (int r = 0; r < rays; ++r)
      if (faces_up_[r]) {
        lowest_[r] = surface_[r] + options_.depth + 1e-9;
        ceiling_ = std::max(ceiling_, lowest_[r]);
      } else {
        lowest_[r] = -kNone;  // not measured: never lowered, never raising the ceiling
      }
    if (ceiling_ == -kNone) return;
    for (const auto& near : near_moves_) {
      lowerTool(frame, grid, moves_[near.second]);
      ceiling_ = -kNone;
      for (int r = 0; r < rays; ++r)
        if (faces_up_[r]) ceiling_ = std::max(ceiling_, lowest_[r]);
    }
  }

  // The first crossing coming down each ray from +depth, and whether its triangle faces up.
  void crossTriangle(const LocalTriangle& t, const RayGrid& grid) {
    const double depth = options_.depth;
    const Vec3 &a = t.a, &b = t.b, &c = t.c;
    const Vec3 normal = (b - a).cross(c - a);
    if (normal.norm() == 0 || std::abs(normal.z()) < 1e-12 * normal.norm()) return;  // along the rays
    if (std::min({a.z(), b.z(), c.z()}) > depth || std::max({a.z(), b.z(), c.z()}) < -depth) return;
    int i0, i1, j0, j1;
    grid.range(grid.first_u, std::min({a.x(), b.x(), c.x()}), std::max({a.x(), b.x(), c.x()}), i0, i1);
    grid.range(grid.first_v, std::min({a.y(), b.y(), c.y()}), std::max({a.y(), b.y(), c.y()}), j0, j1);
    const double area2 = normal.z();  // twice the signed area in the window's plane
    const double sign = area2 > 0 ? 1.0 : -1.0, slack = -1e-12 * std::abs(area2);  // a ray on an edge: both
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double u = grid.u(i), v = grid.v(j);
        // Barycentric weights in the window's plane, times the signed area.
        const double wa = (b.x() - u) * (c.y() - v) - (c.x() - u) * (b.y() - v);
        const double wb = (c.x() - u) * (a.y() - v) - (a.x() - u) * (c.y() - v);
        const double wc = area2 - wa - wb;
        if (sign * wa < slack || sign * wb < slack || sign * wc < slack) continue;
        const double z = (wa * a.z() + wb * b.z() + wc * c.z()) / area2;
        if (z > depth || z < -depth) continue;
        const int r = j * grid.n + i;
        if (z > surface_[r] || (z == surface_[r] && area2 > 0)) {
          surface_[r] = z;
          faces_up_[r] = area2 > 0;
        }
      }
  }

  // The lowest flute point on each ray over the poses of one move near the window.
  void lowerTool(const Frame& frame, const RayGrid& grid, const FeedMove& move) {
    const Flutes& f = flutes_[move.tool];
    if (f.pieces.empty()) return;
    const int steps = poseSteps(move, f, options_.pitch);
    // The poses whose tip lies within the flutes' reach of the window: |tip0 + k delta - p| <= reach.
    const double reach = std::hypot(std::max(std::abs(f.h_min), std::abs(f.h_max)), f.radius) + radius_;
    const Vec3 delta = (move.to.tip - move.from.tip) / steps, w = move.from.tip - frame.origin;
    double lo = 0, hi = steps;
    const double qa = delta.squaredNorm(), qb = 2 * w.dot(delta), qc = w.squaredNorm() - reach * reach;
    if (qa > 0) {
      const double disc = qb * qb - 4 * qa * qc;
      if (disc < 0) return;
      const double root = std::sqrt(disc);
      lo = std::max(lo, (-qb - root) / (2 * qa));
      hi = std::min(hi, (-qb + root) / (2 * qa));
    } else if (qc > 0) {
      return;
    }
    const int k0 = static_cast<int>(std::ceil(lo - 1e-9)), k1 = static_cast<int>(std::floor(hi + 1e-9));
    for (int k = k0; k <= k1; ++k) {
      const ToolPose at = poseAt(move, static_cast<double>(k) / steps);
      const ToolPose local{frame.point(at.tip), frame.direction(at.axis)};
      for (const ToolPiece& piece : f.pieces) lowerPiece(grid, piece, local);
    }
  }

  // The lowest the piece can be over the lattice's square: the sphere's lowest point over it, a frustum's box.
  double lowerBound(const RayGrid& grid, const ToolPiece& piece, const ToolPose& pose, const Box& box) const {
    if (!piece.sphere) return box.min.z();
    const Vec3 centre = pose.tip + piece.centre_h * pose.axis;
    const double side = (grid.n - 1) * grid.pitch;
    const double du = std::max({grid.first_u - centre.x(), 0.0, centre.x() - (grid.first_u + side)});
    const double dv = std::max({grid.first_v - centre.y(), 0.0, centre.y() - (grid.first_v + side)});
    const double d2 = du * du + dv * dv, r2 = piece.sphere_radius * piece.sphere_radius;
    return d2 >= r2 ? kNone : centre.z() - std::sqrt(r2 - d2);
  }

  void lowerPiece(const RayGrid& grid, const ToolPiece& piece, const ToolPose& pose) {
    const Box b = pieceBox(piece, pose);
    if (b.min.z() >= ceiling_ || b.max.z() < -options_.depth) return;
    if (lowerBound(grid, piece, pose, b) >= ceiling_) return;
    int i0, i1, j0, j1;
    grid.range(grid.first_u, b.min.x(), b.max.x(), i0, i1);
    grid.range(grid.first_v, b.min.y(), b.max.y(), j0, j1);
    if (i0 > i1 || j0 > j1) return;
    const PieceOnRays rays(piece, pose, 2);
    Span span;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        ++tests_;
        if (rays.span(grid.u(i), grid.v(j), span)) {
          double& low = lowest_[j * grid.n + i];
          low = std::min(low, span.lo);
        }
      }
  }

  const Mesh& mesh_;
  const std::vector<FeedMove>& moves_;
  const std::vector<Flutes>& flutes_;
  const std::vector<Box>& move_boxes_;
  const std::vector<Block>& blocks_;
  const ScallopProbeOptions& options_;
  double radius_ = 0;  // of the window's bounding sphere
  std::vector<LocalTriangle> triangles_;
  std::vector<std::pair<double, int>> near_moves_;  // squared distance to the window, move
  std::vector<double> surface_, lowest_;
  std::vector<char> faces_up_;
  double ceiling_ = 0;  // the highest lowest_ of a measured ray: a piece entirely above it lowers nothing
  long long tests_ = 0;
};

void checkOptions(const ScallopProbeOptions& o) {
  if (o.windows <= 0 || !(o.half_width > 0) || !(o.pitch > 0) || !(o.depth > 0))
    throw InputError("probeScallops: windows, half_width, pitch and depth must be positive");
  if (2 * o.half_width / o.pitch > 4000)
    throw InputError("probeScallops: more than 4000 rays across a window (half_width / pitch too large)");
}

// Windows drawn over the faces' triangles by area.
std::vector<ScallopWindow> drawWindows(const Mesh& mesh, const std::vector<int>& triangle_face,
                                       const std::vector<int>& faces, const ScallopProbeOptions& options) {
  if (faces.empty()) throw InputError("probeScallops: no face to probe");
  if (triangle_face.size() != mesh.triangles.size())
    throw InputError("probeScallops: triangle_face has " + std::to_string(triangle_face.size()) + " entries for " +
                     std::to_string(mesh.triangles.size()) + " triangles");
  std::vector<int> wanted_faces = faces;
  std::sort(wanted_faces.begin(), wanted_faces.end());
  std::vector<int> triangles;
  std::vector<double> cumulative;
  double total = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    if (!std::binary_search(wanted_faces.begin(), wanted_faces.end(), triangle_face[t])) continue;
    const double area = triangleArea(mesh, t);
    if (!(area > 0)) continue;
    total += area;
    triangles.push_back(t);
    cumulative.push_back(total);
  }
  if (triangles.empty()) throw InputError("probeScallops: the faces asked for have no triangle with area");
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<ScallopWindow> windows(options.windows);
  for (ScallopWindow& w : windows) {
    const double pick = unit(rng) * total;
    const std::size_t i = std::min(triangles.size() - 1, static_cast<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()));
    const int t = triangles[i];
    double s = unit(rng), r = unit(rng);
    if (s + r > 1) s = 1 - s, r = 1 - r;
    w.point = mesh.corner(t, 0) + s * (mesh.corner(t, 1) - mesh.corner(t, 0)) + r * (mesh.corner(t, 2) - mesh.corner(t, 0));
    w.normal = triangleNormal(mesh, t);
    w.face = triangle_face[t];
    w.turn = 2 * kPi * unit(rng);
  }
  return windows;
}

}  // namespace

double ScallopReport::shareWithin(double limit) const {
  int reached = 0, within = 0;
  for (const ScallopWindow& w : windows)
    if (w.fullyReached()) {
      ++reached;
      within += w.max_mm <= limit;
    }
  return reached > 0 ? static_cast<double>(within) / reached : 0.0;
}

double ScallopReport::quantile(double q) const {
  std::vector<double> heights;
  for (const ScallopWindow& w : windows)
    if (w.fullyReached()) heights.push_back(w.max_mm);
  if (heights.empty()) return 0.0;
  std::sort(heights.begin(), heights.end());
  const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * heights.size());
  return heights[std::clamp(static_cast<int>(rank) - 1, 0, static_cast<int>(heights.size()) - 1)];
}

int ScallopReport::fullyReachedCount() const {
  return static_cast<int>(std::count_if(windows.begin(), windows.end(), [](const ScallopWindow& w) { return w.fullyReached(); }));
}

ScallopReport probeScallops(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<int>& faces,
                            const Toolpath& path, const std::vector<Tool>& tools, const ScallopProbeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  checkOptions(options);
  const std::vector<FeedMove> moves = feedMoves(path, tools, "probeScallops");
  const std::vector<Flutes> flutes = flutesOf(tools);
  ScallopReport report;
  report.windows = drawWindows(mesh, triangle_face, faces, options);

  std::vector<Box> move_boxes;
  move_boxes.reserve(moves.size());
  for (const FeedMove& m : moves) move_boxes.push_back(moveBox(m, flutes[m.tool], options.pitch));
  std::vector<Block> blocks;
  for (int first = 0; first < static_cast<int>(moves.size()); first += kMoveBlock) {
    Block b;
    b.first = first;
    b.last = std::min(static_cast<int>(moves.size()), first + kMoveBlock);
    for (int m = b.first; m < b.last; ++m) {
      b.box.extend(move_boxes[m].min);
      b.box.extend(move_boxes[m].max);
    }
    blocks.push_back(b);
  }

  const int threads = std::max(1, std::min(options.windows, options.threads > 0
                                                                ? options.threads
                                                                : static_cast<int>(std::thread::hardware_concurrency())));
  std::atomic<int> next{0};
  std::atomic<long long> tests{0};
  parallelFor(threads, threads, [&](int) {
    Prober prober(mesh, moves, flutes, move_boxes, blocks, options);
    for (int w = next++; w < static_cast<int>(report.windows.size()); w = next++) prober.measure(report.windows[w]);
    tests += prober.tests();
  });
  report.ray_piece_tests = tests;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace art2part
