// An independent measure of radial engagement for the tests: the slab's material as a fine pixel grid, a cutter of
// radius r swept along the moves in steps of a pixel, and at each step the arc of its leading half (ahead of the
// direction of motion) that meets material not yet removed, sampled a pixel and a half outside its edge (inside it the
// step before has removed everything). Nothing of the planner's
// geometry is used: material is the stock polygon test by pixel centre, removal is the disc.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "art2part/roughing/clearing_paths.h"
#include "art2part/roughing/region.h"

namespace art2part {
namespace test {

struct EngagementFigures {
  double cut_mm = 0;           // length of the moves at the level
  double over_mm = 0;          // of which with the engagement above the limit asked
  double worst_deg = 0;        // the largest engagement met
  long material_left = 0;      // pixels of material left within reach (the cutter could have taken them)
  // Of the length judged, where the material met lies mostly on the right of the motion (climb milling with the
  // spindle turning clockwise: each tooth enters the chip at its thickest) and where mostly on the left.
  double climb_mm = 0, conventional_mm = 0;
  // Rapids that end inside the slab (below `top`, above the level) where material lies within the cutter's radius
  // plus `rapid_clearance` of the tool axis (sweep's arguments), and the least gap met at such a rapid's end
  // (negative: material inside the disc).
  int rapids_near_material = 0;
  double least_rapid_gap = 1e300;
};

class EngagementSweep {
 public:
  // Material: pixels whose centre lies in `stock`, over the box of `reach` (where any cutter disc may go).
  EngagementSweep(const Region& stock, const Region& reach, double pixel) : pixel_(pixel) {
    for (int k = 0; k < kSamples; ++k) {
      const double t = 2 * 3.14159265358979323846 * k / kSamples;
      circle_.emplace_back(std::cos(t), std::sin(t));
    }
    Point2 lo(1e18, 1e18), hi(-1e18, -1e18);
    for (const Ring& ring : regionRings(reach))
      for (const Point2& p : ring) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    origin_ = lo - Point2(2 * pixel, 2 * pixel);
    nx_ = static_cast<int>((hi.x() - origin_.x()) / pixel) + 4;
    ny_ = static_cast<int>((hi.y() - origin_.y()) / pixel) + 4;
    material_.assign(static_cast<std::size_t>(nx_) * ny_, 0);
    const RegionLocator in_stock(stock);
    for (int j = 0; j < ny_; ++j)
      for (int i = 0; i < nx_; ++i) material_[index(i, j)] = in_stock.contains(centre(i, j)) ? 1 : 0;
  }

  // Sweeps the moves at height `z` (the cutting ones, and whatever else runs at z) with a cutter of `radius`; the
  // engagement is measured on the moves for which `measured(i)` holds (i: index of the move's end).
  // Rapids ending in the slab, between z and `top`, are judged against the material left when they run: a gap under
  // `rapid_clearance` between the cutter's disc and it counts (EngagementFigures::rapids_near_material).
  template <class Measured>
  EngagementFigures sweep(const std::vector<ClearingPoint>& moves, double z, double radius, double limit_deg,
                          Measured measured, double top = -1e300, double rapid_clearance = 0) {
    EngagementFigures f;
    for (std::size_t i = 1; i < moves.size(); ++i) {
      if (moves[i].move == ClearingMove::Rapid && moves[i].tip.z() > z + 1e-9 && moves[i].tip.z() < top) {
        const double gap = gapToMaterial(moves[i].tip.head<2>(), radius, rapid_clearance + 2 * pixel_);
        f.least_rapid_gap = std::min(f.least_rapid_gap, gap);
        if (gap < rapid_clearance) ++f.rapids_near_material;
      }
      if (moves[i].tip.z() > z + 1e-9 || moves[i - 1].tip.z() > z + 1e-9) {
        if (moves[i].tip.z() <= z + 1e-9) remove(moves[i].tip.head<2>(), radius);  // a plunge's foot
        continue;
      }
      const Point2 a = moves[i - 1].tip.head<2>(), b = moves[i].tip.head<2>();
      const double length = (b - a).norm();
      const int steps = std::max(1, static_cast<int>(std::ceil(length / pixel_)));
      const bool judge = measured(i);
      for (int s = 1; s <= steps; ++s) {
        const Point2 c = a + (b - a) * (static_cast<double>(s) / steps);
        const Engaged engaged = engagedAt(c, (b - a) / std::max(length, 1e-12), radius);
        const double angle = 360.0 * (engaged.right + engaged.left) / kSamples;
        if (judge) {
          f.cut_mm += length / steps;
          if (engaged.right > engaged.left) f.climb_mm += length / steps;
          if (engaged.left > engaged.right) f.conventional_mm += length / steps;
          f.worst_deg = std::max(f.worst_deg, angle);
          if (angle > limit_deg) f.over_mm += length / steps;
        }
        remove(c, radius);
      }
    }
    return f;
  }

  // Material pixels left whose centre lies in `region`.
  long materialIn(const Region& region) const {
    const RegionLocator in(region);
    long n = 0;
    for (int j = 0; j < ny_; ++j)
      for (int i = 0; i < nx_; ++i)
        if (material_[index(i, j)] && in.contains(centre(i, j))) ++n;
    return n;
  }

 private:
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * nx_ + i; }
  Point2 centre(int i, int j) const { return origin_ + pixel_ * Point2(i + 0.5, j + 0.5); }
  bool materialAt(const Point2& p) const {
    const int i = static_cast<int>(std::floor((p.x() - origin_.x()) / pixel_));
    const int j = static_cast<int>(std::floor((p.y() - origin_.y()) / pixel_));
    return i >= 0 && j >= 0 && i < nx_ && j < ny_ && material_[index(i, j)];
  }

  // How far the material left lies outside the disc of `radius` round c (the nearest material pixel's centre, less
  // half a pixel), looked for up to `within` beyond it: `within` when none is that near.
  double gapToMaterial(const Point2& c, double radius, double within) const {
    const double reach = radius + within;
    const int j0 = std::max(0, static_cast<int>(std::floor((c.y() - reach - origin_.y()) / pixel_)));
    const int j1 = std::min(ny_ - 1, static_cast<int>(std::ceil((c.y() + reach - origin_.y()) / pixel_)));
    const int i0 = std::max(0, static_cast<int>(std::floor((c.x() - reach - origin_.x()) / pixel_)));
    const int i1 = std::min(nx_ - 1, static_cast<int>(std::ceil((c.x() + reach - origin_.x()) / pixel_)));
    double nearest = reach + 0.5 * pixel_;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (material_[index(i, j)]) nearest = std::min(nearest, (centre(i, j) - c).norm());
    return std::min(within, nearest - 0.5 * pixel_ - radius);
  }

  // The samples of the leading half of the circle of radius r + 1.5 pixels round c that lie in material (kSamples
  // round the whole circle), right and left of the motion.
  struct Engaged {
    int right = 0, left = 0;
  };
  Engaged engagedAt(const Point2& c, const Point2& direction, double radius) const {
    const double rr = radius + 1.5 * pixel_;
    Engaged in;
    for (const Point2& u : circle_)
      if (u.dot(direction) >= 0 && materialAt(c + rr * u))
        ++(direction.x() * u.y() - direction.y() * u.x() < 0 ? in.right : in.left);
    return in;
  }

  void remove(const Point2& c, double radius) {
    const int j0 = std::max(0, static_cast<int>(std::floor((c.y() - radius - origin_.y()) / pixel_)));
    const int j1 = std::min(ny_ - 1, static_cast<int>(std::ceil((c.y() + radius - origin_.y()) / pixel_)));
    for (int j = j0; j <= j1; ++j) {
      const double dy = centre(0, j).y() - c.y();
      if (std::abs(dy) > radius) continue;
      const double half = std::sqrt(radius * radius - dy * dy);
      const int i0 = std::max(0, static_cast<int>(std::ceil((c.x() - half - origin_.x()) / pixel_ - 0.5)));
      const int i1 = std::min(nx_ - 1, static_cast<int>(std::floor((c.x() + half - origin_.x()) / pixel_ - 0.5)));
      for (int i = i0; i <= i1; ++i) material_[index(i, j)] = 0;
    }
  }

  static constexpr int kSamples = 720;
  double pixel_;
  std::vector<Point2> circle_;  // kSamples unit vectors round the circle
  Point2 origin_;
  int nx_ = 0, ny_ = 0;
  std::vector<unsigned char> material_;
};

}  // namespace test
}  // namespace art2part
