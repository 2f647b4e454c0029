// The exact answer of the visibility definition, by polygon clipping (an oracle for tests and benchmarks).
//
// Triangle t is visible along d when n . d > 0 and some point of t has a clear line to infinity along +d. A point p
// of t is hidden by triangle u exactly when the line p + s d, s > 0, meets u: when p's projection along d lies in the
// projection of the part of u strictly in front of t's plane. So t's visible part, in projection, is t's projection
// minus the union of those projections; t is visible when that leaves area. Per direction every vertex is projected
// once and a grid over the view plane finds the triangles whose shadow can reach t: a few milliseconds per direction
// to set up and tens of microseconds per pair on a 100k-triangle part. Fine for every pair of a small mesh, or for
// chosen pairs of a big one.
#pragma once

#include <utility>
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

// Chosen pairs (triangle, index into directions), grouped by direction internally; answers in the pairs' order.
std::vector<ExactPair> exactVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                                       const std::vector<std::pair<int, int>>& pairs);

// Every (triangle, direction) pair.
VisibilityMap exactVisibility(const Mesh& mesh, const std::vector<Vec3>& directions);

}  // namespace art2part
