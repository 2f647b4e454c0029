// Exact sweeps of cylinders along level and axial moves (cylinder_sweep.h).
#include "art2part/simulation/cylinder_sweep.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace art2part {

namespace {

constexpr double kFar = 1e300;
constexpr int kRowBlock = 4;  // rows per block handed out to the threads in turn
constexpr double kLevelSlackMm = 1e-7;  // a move within this of level (of the axis) is level (axial)

const Span kWholeRay{-kFar, kFar};

// Narrows `range` to where a + t b lies in [lo, hi]; false when nothing is left.
bool within(double a, double b, double lo, double hi, Span& range) {
  if (std::abs(b) < 1e-12) return a >= lo && a <= hi;
  double t0 = (lo - a) / b, t1 = (hi - a) / b;
  if (t0 > t1) std::swap(t0, t1);
  range.lo = std::max(range.lo, t0);
  range.hi = std::min(range.hi, t1);
  return range.lo <= range.hi;
}

// Where (p + t dp)^2 + (q + t dq)^2 <= r^2: a disc met by a line of its plane.
bool inDisc(double p, double dp, double q, double dq, double r, Span& out) {
  const double a = dp * dp + dq * dq, b = 2 * (p * dp + q * dq), c = p * p + q * q - r * r;
  if (a < 1e-12) {
    out = kWholeRay;
    return c <= 0;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return false;
  const double root = std::sqrt(disc);
  out = {(-b - root) / (2 * a), (-b + root) / (2 * a)};
  return true;
}

// A unit vector square to `axis`.
Vec3 across(const Vec3& axis) {
  const Vec3 other = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return axis.cross(other).normalized();
}

Box solidBox(const SweptCylinder& c) {
  Box box;
  box.min = Vec3::Constant(kFar);
  box.max = Vec3::Constant(-kFar);
  const Vec3 spread = (Vec3::Ones() - c.axis.cwiseProduct(c.axis)).cwiseMax(0.0).cwiseSqrt() * c.radius;
  for (const Vec3& tip : {c.from, c.to})
    for (const double h : {c.h0, c.h1}) {
      const Vec3 centre = tip + h * c.axis;
      box.min = box.min.cwiseMin(centre - spread);
      box.max = box.max.cwiseMax(centre + spread);
    }
  return box;
}

}  // namespace

bool sweptCylinders(const ToolPiece& piece, const ToolPose& start, const ToolPose& end, double axial_slack,
                    std::vector<SweptCylinder>& out) {
  if (piece.sphere || piece.r0 != piece.r1 || (start.axis - end.axis).norm() > 1e-12) return false;
  const Vec3 axis = end.axis.normalized(), motion = end.tip - start.tip;
  const double along = motion.dot(axis);
  const Vec3 level = motion - along * axis;
  SweptCylinder c;
  c.axis = axis;
  c.radius = piece.r0;
  if (level.norm() <= kLevelSlackMm && std::abs(along) > kLevelSlackMm) {  // a plunge or a lift
    c.from = c.to = start.tip;
    c.h0 = piece.h0 + std::min(0.0, along);
    c.h1 = piece.h1 + std::max(0.0, along);
    out.push_back(c);
    return true;
  }
  const int pieces = std::abs(along) <= kLevelSlackMm
                         ? 1
                         : static_cast<int>(std::ceil(std::abs(along) / std::max(axial_slack, kLevelSlackMm)));
  const double rise = along / pieces;
  for (int k = 0; k < pieces; ++k) {
    c.from = start.tip + (static_cast<double>(k) / pieces) * motion;
    c.to = c.from + level / pieces;
    c.h0 = piece.h0 + std::min(0.0, rise);
    c.h1 = piece.h1 + std::max(0.0, rise);
    out.push_back(c);
  }
  return true;
}

bool rayThroughSweptCylinder(const SweptCylinder& c, int axis, const Vec3& origin, Span& out) {
  const Vec3 rel = origin - c.from;
  Span range = kWholeRay;
  if (!within(rel.dot(c.axis), c.axis[axis], c.h0, c.h1, range)) return false;
  // In the plane square to the axis: s along the move (0 to its length), w across it.
  const Vec3 move = c.to - c.from;
  const double length = move.norm();
  const Vec3 d = length > 0 ? Vec3(move / length) : across(c.axis), n = c.axis.cross(d);
  const double s = rel.dot(d), ds = d[axis], w = rel.dot(n), dw = n[axis];
  // The stadium is convex: the spans of its two discs and its rectangle on the line join into one.
  Span hit{kFar, -kFar}, piece;
  for (const double end : {0.0, length})
    if (inDisc(s - end, ds, w, dw, c.radius, piece)) hit = {std::min(hit.lo, piece.lo), std::max(hit.hi, piece.hi)};
  piece = kWholeRay;
  if (length > 0 && within(s, ds, 0, length, piece) && within(w, dw, -c.radius, c.radius, piece))
    hit = {std::min(hit.lo, piece.lo), std::max(hit.hi, piece.hi)};
  out = {origin[axis] + std::max(range.lo, hit.lo), origin[axis] + std::min(range.hi, hit.hi)};
  return out.lo < out.hi;
}

void removeSweptCylinders(Stock& stock, const std::vector<SweptCylinder>& solids, int threads) {
  if (solids.empty()) return;
  const DexelLattice& lattice = stock.lattice;
  std::vector<Box> boxes;
  boxes.reserve(solids.size());
  for (const SweptCylinder& c : solids) boxes.push_back(solidBox(c));
  if (threads <= 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const auto work = [&](int thread) {
    for (int axis = 0; axis < 3; ++axis) {
      const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
      for (std::size_t i = 0; i < solids.size(); ++i) {
        const auto us = lattice.indexRange(u, boxes[i].min[u], boxes[i].max[u]);
        const auto vs = lattice.indexRange(v, boxes[i].min[v], boxes[i].max[v]);
        for (int iv = vs[0]; iv <= vs[1]; ++iv) {
          if ((iv / kRowBlock) % threads != thread) continue;
          for (int iu = us[0]; iu <= us[1]; ++iu) {
            SpanList& spans = stock.ray(axis, lattice.rayIndex(axis, iu, iv));
            Span cut;
            if (!spans.empty() && rayThroughSweptCylinder(solids[i], axis, lattice.rayOrigin(axis, iu, iv), cut))
              subtractSpan(spans, cut, nullptr);
          }
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
}

}  // namespace art2part
