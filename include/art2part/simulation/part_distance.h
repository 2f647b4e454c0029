// Distance from a point to the part's surface: Embree's BVH point query with an exact closest point on each candidate
// triangle. Gouge depths and the deviation of the remaining stock are measured with it. Thread-safe after
// construction.
#pragma once

#include <limits>
#include <memory>

#include "art2part/geometry/mesh.h"

namespace art2part {

class PartDistance {
 public:
  explicit PartDistance(const Mesh& mesh);
  ~PartDistance();
  PartDistance(const PartDistance&) = delete;
  PartDistance& operator=(const PartDistance&) = delete;

  // Unsigned distance to the nearest triangle (infinity for an empty mesh); `triangle` gets that triangle. With
  // `max_distance`, triangles farther than it are not searched (infinity when none is nearer): much faster far away.
  double distance(const Vec3& point, int* triangle = nullptr,
                  double max_distance = std::numeric_limits<double>::infinity()) const;

 private:
  struct Scene;
  std::unique_ptr<Scene> scene_;
};

// The point of triangle abc nearest to p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace art2part
