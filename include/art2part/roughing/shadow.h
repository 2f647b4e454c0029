// Shadows (thesis 5.1 step 7): at a level z the tool reaches only what no part material above z covers. The shadow of
// a part at z is the projection, along the setup direction, of the part above z; for a closed mesh it is the union of
// the projections of its up-facing triangles clipped to {z' >= z}. We project every non-vertical triangle (the same
// union on a closed mesh, and no hole where a triangle is wound the wrong way), slab by slab from the top.
// Also the stock's projection per slab. Everything in a setup frame (x, y in the slice plane, z along the direction).
#pragma once

#include <functional>
#include <map>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/roughing/region.h"
#include "art2part/setup/setup_plan.h"

namespace art2part {

// Vertex coordinates in a setup frame: (p - origin) . (x, y, z).
std::vector<Vec3> toFrame(const std::vector<Vec3>& points, const SetupFrame& frame);
Vec3 fromFrame(const Vec3& p, const SetupFrame& frame);  // back to the part frame

constexpr double kThinGain = 0.002;  // mm

// Shadows at a set of heights, for queries at any height: the shadow at the highest stored height at or below the one
// asked (a superset of the exact shadow there, exact at the stored heights), empty above the part. Queries below the
// lowest stored height are refused (std::out_of_range). Built by SetupShadows.
class ShadowStack {
 public:
  ShadowStack(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, std::vector<double> heights);
  const Region& at(double z) const;
  // The index of the stored height whose shadow at(z) is, -1 where at(z) is empty (above the part); and what the
  // shadow at stored height i gained over the one above it (pieces, disjoint from that shadow: the shadow at i is the
  // union of the gains 0..i, up to slivers within 2 kThinGain of it). Together they let a caller grow an offset
  // shadow level by level from the gains alone.
  int indexAt(double z) const;
  const Region& gain(int i) const { return gains_[i]; }

 private:
  friend class SetupShadows;
  ShadowStack() = default;
  std::vector<double> heights_;  // descending
  std::vector<Region> shadows_, gains_;
  double part_top_ = 0;
  Region empty_;
};

// The shadows of one part in one setup frame, each height's computed once and kept. The shadow at z is the nearest
// kept one above it united with the pieces, between the two heights, of the triangles reaching into that slab (every
// non-vertical triangle: for a closed mesh the up-facing ones would do, but a triangle wound the wrong way must not
// open a hole, and the down-facing ones lie under material above anyway). The operations of a setup (the tool
// choice, main, reach and rest passes) ask at levels that mostly repeat, and share the work; asked in descending
// order alone it is the sweep from the top that a single stack would make.
class SetupShadows {
 public:
  // `vertices` in the setup frame, the mesh's triangles.
  SetupShadows(std::vector<Vec3> vertices, const std::vector<Triangle>& triangles);
  // The shadow at z (material exactly at z counts as above it).
  const Region& at(double z) { return keep(z).shadow; }
  // The shadows at `heights` (any order, repeats allowed). A stack's gain at a height lists the kept gains of every
  // kept height between it and the stack's height above (each gain is what its height added to the kept shadow above
  // it when it was computed: pieces may repeat across heights, never go missing).
  ShadowStack stack(std::vector<double> heights);

 private:
  struct Kept {
    Region shadow;
    // What it added to the kept shadow above it, less its pieces thinner than 2 kThinGain everywhere (slivers of a
    // wall a hair off the direction, thousands of them per level, whose offsets would cost as much as the outline's).
    Region gain;
  };
  const Kept& keep(double z);
  std::vector<Vec3> vertices_;
  std::vector<Triangle> up_;        // non-vertical triangles, highest top first
  std::vector<double> top_, bottom_;
  double part_top_;
  std::map<double, Kept, std::greater<double>> kept_;  // highest first
};

// The projection of the stock between heights lo and hi (its convex hull there: exact for a box, conservative for a
// non-convex stock mesh). `vertices` in the setup frame.
Region stockSlabRegion(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, double lo, double hi);

// A closed box mesh (12 triangles, outward).
Mesh boxMesh(const Box& box);

}  // namespace art2part
