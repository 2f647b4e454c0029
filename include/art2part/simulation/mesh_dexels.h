// A closed mesh (the part, or a stock given as a mesh) dexelized on a tri-dexel lattice: along every ray, the spans
// inside the mesh, each end knowing the triangle it crosses (for the surface normal there and the face).
//
// Exact scan conversion, no ray casting: each triangle is rasterised onto the ray grid of each family, the crossing
// depth taken from its plane. A ray through an edge or a vertex is decided by one symbolic perturbation of the ray
// (edges are evaluated in a canonical vertex order, ties broken by the edge direction), so two triangles sharing an
// edge never both count it nor both miss it: a closed mesh gives balanced entries and exits on every ray. Spans are
// where the winding number is not zero (nested or overlapping shells merge, a mesh turned inside out still works); a
// ray left unbalanced by a hole in an open mesh drops its unclosed span.
#pragma once

#include <array>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/simulation/dexel.h"

namespace art2part {

struct SolidSpan {
  double lo = 0, hi = 0;
  int lo_triangle = -1, hi_triangle = -1;  // crossed where the ray enters (lo) and leaves (hi)
};

class MeshDexels {
 public:
  MeshDexels() = default;
  MeshDexels(const Mesh& mesh, const DexelLattice& lattice);

  const DexelLattice& lattice() const { return lattice_; }
  const SolidSpan* begin(int axis, int ray) const { return spans_[axis].data() + offsets_[axis][ray]; }
  const SolidSpan* end(int axis, int ray) const { return spans_[axis].data() + offsets_[axis][ray + 1]; }
  SpanList spans(int axis, int ray) const;
  bool contains(int axis, int ray, double t) const;
  // The nearest lattice ray of `axis` to the point: whether the point lies inside along it.
  bool containsNear(const Vec3& point, int axis = 2) const;
  // Unit normal of each triangle (zero for a degenerate one).
  const std::vector<Vec3>& normals() const { return normals_; }
  double volume() const;  // mean over the three families

 private:
  DexelLattice lattice_;
  std::array<std::vector<int>, 3> offsets_;
  std::array<std::vector<SolidSpan>, 3> spans_;
  std::vector<Vec3> normals_;
};

}  // namespace art2part
