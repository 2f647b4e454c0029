// Internal to surface finishing: what lies around a tool axis of any direction. The part's triangles in a uniform 3-D
// grid; a query walks the cells near the axis line above a height and finds, exactly per triangle, the highest point
// (along the axis) within a radius of the line: the flat drop-cutter along that axis.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part::surface {

// The triangle that answered a query last (consecutive poses meet the same material: trying it first ends most
// colliding queries at once). One per caller and kind of query.
struct ProbeHint {
  int triangle = -1;
};

class AxisProbe {
 public:
  explicit AxisProbe(const Mesh& mesh);
  // The highest axial coordinate (from `tip` along unit `axis`) of the part's points within `radius` of the axis line
  // whose coordinate exceeds `from`; -infinity when there is none. Thread-safe.
  double highest(const Vec3& tip, const Vec3& axis, double radius, double from) const;
  // Whether any such point exists (stops at the first).
  bool any(const Vec3& tip, const Vec3& axis, double radius, double from, ProbeHint& hint) const;

 private:
  // Triangles by bounding box in a uniform grid; several grids, each cell twice the last's, so that a query's
  // neighbourhood spans a few cells whatever its radius.
  struct Level {
    double cell = 1;
    int n[3] = {0, 0, 0};
    std::vector<int> start, items;
  };
  double scan(const Vec3& tip, const Vec3& axis, double radius, double from, bool first, ProbeHint* hint) const;
  double triangleHighest(int t, const Vec3& tip, const Vec3& e1, const Vec3& e2, const Vec3& axis, double radius,
                         double above) const;

  const Mesh& mesh_;
  Box box_;
  std::vector<Level> levels_;
};

}  // namespace art2part::surface
