// The highest part point within a radius of an axis line of any direction (axis_probe.h).
#include "axis_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace art2part::surface {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The grid's cell: this share of the box's diagonal, at least kMinCell mm (a few cells per tool radius).
constexpr double kCellOfDiagonal = 1.0 / 64;
constexpr double kMinCell = 1.0;

// The highest w over the points of triangle (u, v, w) with u^2 + v^2 <= rho^2: a vertex inside, where an edge crosses
// the circle, or the plane's highest point on the circle when that lies inside the triangle.
double highestInDisc(const Vec3 p[3], double rho) {
  const double r2 = rho * rho;
  double best = -kInf;
  for (int k = 0; k < 3; ++k)
    if (p[k].x() * p[k].x() + p[k].y() * p[k].y() <= r2) best = std::max(best, p[k].z());
  for (int k = 0; k < 3; ++k) {
    const Vec3& a = p[k];
    const Vec3 d = p[(k + 1) % 3] - a;
    const double A = d.x() * d.x() + d.y() * d.y();
    if (A <= 0) continue;
    const double B = a.x() * d.x() + a.y() * d.y(), C = a.x() * a.x() + a.y() * a.y() - r2;
    const double disc = B * B - A * C;
    if (disc < 0) continue;
    const double root = std::sqrt(disc);
    for (double t : {(-B - root) / A, (-B + root) / A})
      if (t >= 0 && t <= 1) best = std::max(best, a.z() + t * d.z());
  }
  const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
  const double nuv = std::hypot(n.x(), n.y());
  if (std::abs(n.z()) > 1e-12 * n.norm() && nuv > 0) {
    // w rises along -(n_u, n_v) / n_w: the highest point of the plane on the circle.
    const double s = n.z() > 0 ? -1 : 1;
    const double u = s * rho * n.x() / nuv, v = s * rho * n.y() / nuv;
    double side[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = p[k];
      const Vec3& b = p[(k + 1) % 3];
      side[k] = (b.x() - a.x()) * (v - a.y()) - (b.y() - a.y()) * (u - a.x());
    }
    if ((side[0] >= 0 && side[1] >= 0 && side[2] >= 0) || (side[0] <= 0 && side[1] <= 0 && side[2] <= 0))
      best = std::max(best, p[0].z() - (n.x() * (u - p[0].x()) + n.y() * (v - p[0].y())) / n.z());
  }
  return best;
}

}  // namespace

AxisProbe::AxisProbe(const Mesh& mesh) : mesh_(mesh) {
  box_ = boundingBox(mesh);
  if (box_.empty()) return;
  for (double cell = std::max(kMinCell, kCellOfDiagonal * box_.diagonal());; cell *= 2) {
    Level level;
    level.cell = cell;
    for (int a = 0; a < 3; ++a) level.n[a] = static_cast<int>((box_.max[a] - box_.min[a]) / cell) + 1;
    const std::size_t cells = static_cast<std::size_t>(level.n[0]) * level.n[1] * level.n[2];
    std::vector<std::pair<int, int>> pairs;
    for (int t = 0; t < mesh.triangleCount(); ++t) {
      int lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        double mn = kInf, mx = -kInf;
        for (int k = 0; k < 3; ++k) mn = std::min(mn, mesh.corner(t, k)[a]), mx = std::max(mx, mesh.corner(t, k)[a]);
        lo[a] = std::clamp(static_cast<int>((mn - box_.min[a]) / cell), 0, level.n[a] - 1);
        hi[a] = std::clamp(static_cast<int>((mx - box_.min[a]) / cell), 0, level.n[a] - 1);
      }
      for (int i = lo[0]; i <= hi[0]; ++i)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int k = lo[2]; k <= hi[2]; ++k) pairs.emplace_back((k * level.n[1] + j) * level.n[0] + i, t);
    }
    level.start.assign(cells + 1, 0);
    for (const auto& p : pairs) ++level.start[p.first + 1];
    for (std::size_t c = 1; c <= cells; ++c) level.start[c] += level.start[c - 1];
    level.items.resize(pairs.size());
    std::vector<int> fill(level.start.begin(), level.start.end() - 1);
    for (const auto& p : pairs) level.items[fill[p.first]++] = p.second;
    levels_.push_back(std::move(level));
    if (cell > box_.diagonal()) break;
  }
}

double AxisProbe::triangleHighest(int t, const Vec3& tip, const Vec3& e1, const Vec3& e2, const Vec3& axis,
                                  double radius, double above) const {
  Vec3 p[3];
  for (int m = 0; m < 3; ++m) {
    const Vec3 d = mesh_.corner(t, m) - tip;
    p[m] = Vec3(d.dot(e1), d.dot(e2), d.dot(axis));
  }
  if (std::max({p[0].z(), p[1].z(), p[2].z()}) <= above) return -kInf;
  const double h = highestInDisc(p, radius);
  return h > above ? h : -kInf;
}

double AxisProbe::highest(const Vec3& tip, const Vec3& axis, double radius, double from) const {
  return scan(tip, axis, radius, from, false, nullptr);
}

bool AxisProbe::any(const Vec3& tip, const Vec3& axis, double radius, double from, ProbeHint& hint) const {
  if (hint.triangle >= 0 && hint.triangle < mesh_.triangleCount()) {
    const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
    if (triangleHighest(hint.triangle, tip, e1, e2, axis, radius, from) > from) return true;
  }
  return scan(tip, axis, radius, from, true, &hint) > from;
}

double AxisProbe::scan(const Vec3& tip, const Vec3& axis, double radius, double from, bool first,
                       ProbeHint* hint) const {
  if (box_.empty()) return -kInf;
  // The stretch of the axis line whose neighbourhood of `radius` meets the box, above `from`.
  double w0 = from, w1 = kInf;
  for (int a = 0; a < 3; ++a) {
    const double lo = box_.min[a] - radius, hi = box_.max[a] + radius;
    if (std::abs(axis[a]) < 1e-12) {
      if (tip[a] < lo || tip[a] > hi) return -kInf;
      continue;
    }
    double t0 = (lo - tip[a]) / axis[a], t1 = (hi - tip[a]) / axis[a];
    if (t0 > t1) std::swap(t0, t1);
    w0 = std::max(w0, t0);
    w1 = std::min(w1, t1);
  }
  if (!(w0 <= w1)) return -kInf;
  // The grid whose cells are at least half the radius: a few cells each way of each sample.
  const Level* level = &levels_.back();
  for (const Level& l : levels_)
    if (l.cell >= 0.5 * radius) {
      level = &l;
      break;
    }
  const double cell = level->cell;
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  // Every cell whose centre lies within radius + its half diagonal of the stretch, once.
  thread_local std::vector<int> seen;
  thread_local int query = 0;
  if (seen.size() != static_cast<std::size_t>(mesh_.triangleCount())) seen.assign(mesh_.triangleCount(), 0), query = 0;
  if (++query == 0) std::fill(seen.begin(), seen.end(), 0), query = 1;
  const double reach = radius + 0.8661 * cell;
  const Vec3 c0 = tip + w0 * axis, c1 = tip + w1 * axis;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, static_cast<int>(std::floor((std::min(c0[a], c1[a]) - reach - box_.min[a]) / cell)));
    hi[a] = std::min(level->n[a] - 1, static_cast<int>(std::floor((std::max(c0[a], c1[a]) + reach - box_.min[a]) / cell)));
  }
  double best = -kInf;
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        const Vec3 centre = box_.min + cell * Vec3(i + 0.5, j + 0.5, k + 0.5);
        const double w = std::clamp((centre - tip).dot(axis), w0, w1);
        if ((centre - tip - w * axis).squaredNorm() > reach * reach) continue;
        const int id = (k * level->n[1] + j) * level->n[0] + i;
        for (int q = level->start[id]; q < level->start[id + 1]; ++q) {
          const int t = level->items[q];
          if (seen[t] == query) continue;
          seen[t] = query;
          const double h = triangleHighest(t, tip, e1, e2, axis, radius, std::max(from, best));
          if (h > best) {
            best = h;
            if (first) {
              hint->triangle = t;
              return best;
            }
          }
        }
      }
  return best;
}

}  // namespace art2part::surface
