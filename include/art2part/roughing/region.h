// Planar regions for roughing (thesis 4.1.2): sets of points in a slice plane as Clipper polygons (Debian's
// libpolyclipping 6.4), outer rings counter-clockwise and holes clockwise, in integer units of 0.1 um. Union,
// difference, intersection and round offsets by a tool radius are Clipper's; the rest (area, point and segment tests,
// conversion to mm) is here.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <polyclipping/clipper.hpp>
#include <vector>

namespace art2part {

using Point2 = Eigen::Vector2d;
using Ring = std::vector<Point2>;   // a closed polygon in mm, last point not repeated
using Region = ClipperLib::Paths;   // a set of points: rings in integer units (kRegionScale per mm)

constexpr double kRegionScale = 1e4;  // integer units per mm

ClipperLib::IntPoint toRegionPoint(const Point2& p);
Point2 fromRegionPoint(const ClipperLib::IntPoint& p);

// The union of polygons of any orientation (each counts as filled, whatever its winding).
Region regionFromPolygons(const std::vector<Ring>& polygons);
std::vector<Ring> regionRings(const Region& region);  // mm; outer rings CCW, holes CW

Region unite(const Region& a, const Region& b);
Region subtract(const Region& a, const Region& b);
Region intersect(const Region& a, const Region& b);
// Minkowski sum with a disc of radius `mm` (negative: erosion), round joins followed within `arc_tolerance` mm
// (chords inside the true arcs, so the result is smaller than the exact sum by at most that).
constexpr double kArcTolerance = 0.005;
Region offsetRegion(const Region& region, double mm, double arc_tolerance = kArcTolerance);
// Douglas-Peucker on every ring: vertices dropped while the ring stays within `tolerance` mm of the original, so
// every point of the region lies within `tolerance` of the result and the other way round (offset the result by
// `tolerance` more to cover the original). A ring that would shrink below three vertices is kept as it is.
Region simplifyRegion(const Region& region, double tolerance);
// Drops the pieces (outer ring with its holes) that an erosion by `half_width` empties: slivers thinner than twice
// it everywhere. Pieces that survive stay whole.
Region dropThinPieces(const Region& region, double half_width);
// Drops rings whose area is below `min_area_mm2` (slivers left by offsets), with their holes.
Region dropSlivers(const Region& region, double min_area_mm2);
// Fills the holes whose area is below `max_area_mm2`: a hole smaller than a disc of radius r cannot hold one, so a
// region grown by r is the same with them filled (and far cheaper to grow: a shadow seen along a wall has thousands).
// The region must be well-formed (Clipper's output: holes clockwise).
Region fillSmallHoles(const Region& region, double max_area_mm2);

double regionArea(const Region& region);  // mm^2, holes subtracted
// Counts the boolean operations and offsets Clipper reported as failed (their results are unreliable) on this thread
// while it lives: a diagnostic the roughing stage reports. Tallies nest: an inner one's count goes to the one it
// was opened in when it closes. Not copyable; open and close it on one thread.
class RegionFailureTally {
 public:
  RegionFailureTally();
  ~RegionFailureTally();
  RegionFailureTally(const RegionFailureTally&) = delete;
  RegionFailureTally& operator=(const RegionFailureTally&) = delete;
  long count() const { return count_; }
  static void countFailure();  // a failure on this thread: to its innermost tally, if any
  static void countFailures(long n);  // n of them

 private:
  long count_ = 0;
  RegionFailureTally* outer_;
};
// parallelFor (common/parallel.h) on the machine's threads, with the Clipper failures on them counted on this thread's
// innermost tally as if they had been its own.
void parallelForRegions(int count, const std::function<void(int)>& body);

bool regionEmpty(const Region& region);
// Inside or on the boundary.
bool regionContains(const Region& region, const Point2& p);
// mm from `p` to the region: 0 inside or on it, else to its nearest ring edge (infinity for an empty region).
double regionDistance(const Region& region, const Point2& p);
// The rings whose bounding boxes meet the box [lo, hi] (mm): the same set as the region within that box (a hole's
// box lies within its outer ring's), usually far fewer edges for a boolean operation with something small.
Region ringsMeeting(const Region& region, const Point2& lo, const Point2& hi);

// regionContains for many points of one region: its edges bucketed into horizontal bands, so a query looks at the
// edges of its band only (a winding number by the crossings of a ray towards +x) instead of every ring. The same
// answers as regionContains (boundary inside). Keeps no reference to the region.
class RegionLocator {
 public:
  RegionLocator() = default;
  explicit RegionLocator(const Region& region);
  bool contains(const Point2& p) const;

 private:
  struct Edge {
    ClipperLib::IntPoint a, b;  // as the ring runs
  };
  ClipperLib::cInt y0_ = 0, band_ = 1;
  std::vector<std::vector<Edge>> bands_;
};

// The whole segment a-b lies in the region (boundary included): cut wherever it meets a ring (crossing, touching a
// vertex, running along an edge), the middle of each piece is inside, or the piece runs along an edge.
bool segmentInside(const Region& region, const Point2& a, const Point2& b);

// Outer rings with their holes: the connected pieces of a region (Clipper's PolyTree).
struct RegionPiece {
  Region rings;  // the outer ring first, then its holes
  double area_mm2 = 0;
};
std::vector<RegionPiece> regionPieces(const Region& region);

}  // namespace art2part
