// The exact answer of the visibility definition, by polygon clipping (an oracle for tests and benchmarks).
//
// Triangle t is visible along d when n . d > 0 and some point of t has a clear line to infinity along +d. A point p
// of t is hidden by triangle u exactly when the line p + s d, s > 0, meets u: when p's projection along d lies in the
// projection of the part of u strictly in front of t's plane. So t's visible part, in projection, is t's projection
// minus the union of those projections; t is visible when that leaves area. Brute force over every triangle: fine
// for meshes of a few thousand triangles, or for chosen pairs of a big one.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/visibility/visibility_map.h"

namespace art2part {

struct ExactPair {
  bool visible = false;    // front-facing and uncovered > kExactMinUncovered
  double uncovered = 0;    // fraction of t's projected area that sees out (0 when back-facing or edge-on)
  Vec3 witness = Vec3::Zero();  // when visible: a point of t inside its largest visible piece (its vertex mean)
};

// Fractions of a triangle's projected area at or below this are rounding (the clipping works in integers, about
// 2^28 units across the triangle): not visible.
constexpr double kExactMinUncovered = 1e-6;

// d need not be unit. Degenerate triangles are never visible and never hide anything.
ExactPair exactVisibility(const Mesh& mesh, int t, const Vec3& d);

// Every (triangle, direction) pair: O(triangles^2 x directions).
VisibilityMap exactVisibility(const Mesh& mesh, const std::vector<Vec3>& directions);

}  // namespace art2part
