#include "art2part/roughing/link_clearance.h"

#include <algorithm>
#include <cmath>

#include "art2part/roughing/forbidden_region.h"

namespace art2part {

namespace {

constexpr double kAboveHolder = 1e9;  // the spindle side above the holder: as wide as the holder's widest step
// mm: a centre point lies a tool radius from its swept disc's rim, to rounding and to the rim's chords
// (offsetRegion follows the circle within kArcTolerance, inside it).
constexpr double kGridSlack = kArcTolerance + 1e-3;
constexpr double kFar = 1e300;        // no stock within reach

double segmentDistance(const Point2& a, const Point2& b, const Point2& p, const Point2& q) {
  auto pointToSegment = [](const Point2& x, const Point2& s0, const Point2& s1) {
    const Point2 d = s1 - s0;
    const double t = d.squaredNorm() > 0 ? std::clamp((x - s0).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    return (s0 + t * d - x).norm();
  };
  auto cross = [](const Point2& u, const Point2& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double o1 = cross(b - a, p - a), o2 = cross(b - a, q - a), o3 = cross(q - p, a - p), o4 = cross(q - p, b - p);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 0;
  return std::min({pointToSegment(p, a, b), pointToSegment(q, a, b), pointToSegment(a, p, q), pointToSegment(b, p, q)});
}

}  // namespace

LinkClearance::LinkClearance(const Tool& tool, double margin, Beside beside) : margin_(margin) {
  const double cutter = tool.diameter / 2;
  auto withMargin = [&](double radius) {
    return radius <= cutter && beside == Beside::BodyOnly ? radius - kGridSlack : radius + margin;
  };
  zones_.push_back({0, tool.flute_length, withMargin(cutter)});
  double top = tool.flute_length, widest = cutter;
  for (const BodyZone& zone : bodyZones(tool)) {
    zones_.push_back({zone.from, zone.to, withMargin(zone.radius)});
    top = std::max(top, zone.to);
    widest = std::max(widest, zone.radius);
  }
  zones_.push_back({top, kAboveHolder, withMargin(widest)});
  widest_ = zones_.back().radius;
}

LinkClearance::Slab LinkClearance::slabOf(const SlabState& slab, const Region& swept) {
  Slab s;
  s.z = slab.z;
  s.top = slab.top;
  s.remaining = regionEmpty(swept) ? slab.remaining : subtract(slab.remaining, swept);
  s.lo = Point2::Constant(1e300);
  s.hi = Point2::Constant(-1e300);
  for (const Ring& ring : regionRings(s.remaining))
    for (std::size_t i = 0; i < ring.size(); ++i) {
      s.edges.push_back({ring[i], ring[(i + 1) % ring.size()]});
      s.lo = s.lo.cwiseMin(ring[i]);
      s.hi = s.hi.cwiseMax(ring[i]);
    }
  return s;
}

void LinkClearance::addSlab(const SlabState& slab, const Region& swept) { slabs_.push_back(slabOf(slab, swept)); }

void LinkClearance::replaceSlab(std::size_t index, const SlabState& slab, const Region& swept) {
  slabs_.at(index) = slabOf(slab, swept);
}

double LinkClearance::distanceTo(const Slab& slab, const Point2& a, const Point2& b, double beyond) {
  if (slab.edges.empty()) return kFar;
  const Point2 lo = a.cwiseMin(b) - Point2::Constant(beyond), hi = a.cwiseMax(b) + Point2::Constant(beyond);
  if ((lo.array() > slab.hi.array()).any() || (hi.array() < slab.lo.array()).any()) return kFar;
  if (regionContains(slab.remaining, a) || regionContains(slab.remaining, b)) return 0;
  double nearest = kFar;
  for (const Edge& e : slab.edges) {
    if (std::max(e.a.x(), e.b.x()) < lo.x() || std::min(e.a.x(), e.b.x()) > hi.x() ||
        std::max(e.a.y(), e.b.y()) < lo.y() || std::min(e.a.y(), e.b.y()) > hi.y())
      continue;
    nearest = std::min(nearest, segmentDistance(a, b, e.a, e.b));
    if (nearest == 0) break;
  }
  return nearest;
}

bool LinkClearance::clearAt(const Point2& a, const Point2& b, double height) const {
  for (const Zone& zone : zones_)
    for (const Slab& slab : slabs_)
      if (slab.top + margin_ > height + zone.from && slab.z < height + zone.to &&
          distanceTo(slab, a, b, zone.radius) < zone.radius)
        return false;
  return true;
}

double LinkClearance::lowestClear(const Point2& a, const Point2& b, double lowest, double ceiling) const {
  // Each slab the body would meet sets a floor: the lowest zone whose radius reaches it must pass `margin_` over its
  // top, and so must every zone above (they start higher). The zones below it do not reach it at any height.
  double height = lowest;
  for (const Slab& slab : slabs_) {
    if (slab.top + margin_ <= height) continue;  // under the tip wherever the tool goes
    const double distance = distanceTo(slab, a, b, widest_);
    for (const Zone& zone : zones_)
      if (distance < zone.radius) {
        height = std::max(height, slab.top + margin_ - zone.from + 1e-6);
        break;
      }
    if (height >= ceiling) return ceiling;
  }
  return clearAt(a, b, height) ? height : ceiling;
}

}  // namespace art2part
