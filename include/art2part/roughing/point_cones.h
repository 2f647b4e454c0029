// Visibility cones of points of the delta volume (thesis 3.2.5, Algorithm 3, evaluated where roughing asks): the
// sampled directions along which a straight line from a point escapes the part. volume_visibility.h fills a whole
// voxel grid with height maps (seconds per setup on a 400 mm part); 5-axis roughing needs the cones of a few
// thousand voxels of material that 3-axis roughing left, so here each is cast as rays (Embree, the mesh's BVH built
// once), only along the directions of a given reach.
#pragma once

#include <atomic>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/cones.h"

namespace art2part {

class PointCones {
 public:
  // The part in its own frame; `directions` the sampled sphere the cones are over.
  PointCones(const Mesh& part, const DirectionSet& directions);
  ~PointCones();
  PointCones(const PointCones&) = delete;
  PointCones& operator=(const PointCones&) = delete;

  // Directions of `among` (a cone over the same set) along which the ray from p meets no triangle. Thread-safe.
  Cone coneAt(const Vec3& p, const Cone& among) const;
  // Whether the ray from p along the unit direction d meets no triangle.
  bool escapes(const Vec3& p, const Vec3& d) const;
  std::size_t raysCast() const { return rays_.load(); }  // by coneAt, so far

 private:
  const DirectionSet& directions_;
  void* device_ = nullptr;
  void* scene_ = nullptr;
  Vec3 centre_ = Vec3::Zero();  // Embree works in float, relative to the part's box centre
  mutable std::atomic<std::size_t> rays_{0};
};

}  // namespace art2part
