// Shadows (thesis 5.1 step 7): at a level z the tool reaches only what no part material above z covers. The shadow of
// a part at z is the projection, along the setup direction, of the part above z; for a closed mesh it is the union of
// the projections of its up-facing triangles clipped to {z' >= z}. We project every non-vertical triangle (the same
// union on a closed mesh, and no hole where a triangle is wound the wrong way), slab by slab from the top.
// Also the stock's projection per slab. Everything in a setup frame (x, y in the slice plane, z along the direction).
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/roughing/region.h"
#include "art2part/setup/setup_plan.h"

namespace art2part {

// Vertex coordinates in a setup frame: (p - origin) . (x, y, z).
std::vector<Vec3> toFrame(const std::vector<Vec3>& points, const SetupFrame& frame);
Vec3 fromFrame(const Vec3& p, const SetupFrame& frame);  // back to the part frame

constexpr double kThinGain = 0.002;  // mm

class ShadowSweep {
 public:
  // `vertices` in the setup frame, the mesh's triangles (outward, counter-clockwise seen from outside).
  ShadowSweep(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles);
  // The shadow at z; calls must come with z decreasing. Material exactly at z counts as above it.
  const Region& shadowAt(double z);
  int slabTriangles() const { return slab_triangles_; }  // triangle pieces projected so far
  // What the last shadowAt added to the shadow before it, less its pieces thinner than 2 kThinGain everywhere: disjoint
  // from it, so the shadow lies within 2 kThinGain of the union of the gains (slivers of a wall a hair off the
  // direction, thousands of them per level, whose offsets would cost as much as the whole outline's).
  const Region& lastGain() const { return gain_; }

 private:
  std::vector<Vec3> vertices_;
  std::vector<Triangle> up_;        // non-vertical triangles, highest top first
  std::vector<double> top_, bottom_;
  std::size_t next_ = 0;            // first triangle of up_ not yet entered
  std::vector<int> active_;         // entered triangles reaching below the previous level
  double previous_z_;
  Region shadow_, gain_;
  int slab_triangles_ = 0;
};

// Shadows at a set of heights, for queries at any height: the shadow at the highest stored height at or below the one
// asked (a superset of the exact shadow there, exact at the stored heights), empty above the part. Queries below the
// lowest stored height are refused (std::out_of_range).
class ShadowStack {
 public:
  ShadowStack(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, std::vector<double> heights);
  const Region& at(double z) const;
  int slabTriangles() const { return slab_triangles_; }
  // The index of the stored height whose shadow at(z) is, -1 where at(z) is empty (above the part); and what the
  // shadow at stored height i gained over the one above it (disjoint pieces: the shadow at i is the union of the
  // gains 0..i, up to slivers within 2 kThinGain of it). Together they let a caller grow an offset shadow level by
  // level from the gains alone.
  int indexAt(double z) const;
  const Region& gain(int i) const { return gains_[i]; }

 private:
  std::vector<double> heights_;  // descending
  std::vector<Region> shadows_, gains_;
  double part_top_ = 0;
  Region empty_;
  int slab_triangles_ = 0;
};

// The projection of the stock between heights lo and hi (its convex hull there: exact for a box, conservative for a
// non-convex stock mesh). `vertices` in the setup frame.
Region stockSlabRegion(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, double lo, double hi);

// A closed box mesh (12 triangles, outward).
Mesh boxMesh(const Box& box);

}  // namespace art2part
