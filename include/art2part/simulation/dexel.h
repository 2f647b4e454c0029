// Dexels: material along rays, as sorted lists of spans. A tri-dexel lattice has three families of parallel rays over
// a box, one family along each axis. Family k runs along axis k; its rays sit at the cell centres of the grid over the
// other two axes u = (k + 1) % 3 and v = (k + 2) % 3, so rays of the three families cross at the lattice points (the
// cell centres of the 3D grid) and a span's ends are exact coordinates along its ray, not rounded to cells.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

struct Span {
  double lo = 0, hi = 0;  // coordinates along the ray, lo < hi
  double length() const { return hi - lo; }
};

// Sorted, disjoint spans of material along one ray.
using SpanList = std::vector<Span>;

struct DexelLattice {
  Box box;                          // what the rays cover
  std::array<int, 3> cells{0, 0, 0};  // cells per axis
  Vec3 spacing = Vec3::Zero();      // cell size per axis (box size / cells: at most the resolution asked for)

  // Cells of at most `resolution` that tile the box exactly. Throws InputError for an empty box or a resolution that
  // is not positive or makes more than `max_rays` rays (about 80 bytes each).
  static DexelLattice over(const Box& box, double resolution, std::int64_t max_rays = 8000000);

  static int uAxis(int axis) { return (axis + 1) % 3; }
  static int vAxis(int axis) { return (axis + 2) % 3; }
  int rayCount(int axis) const { return cells[uAxis(axis)] * cells[vAxis(axis)]; }
  std::int64_t totalRays() const;
  int rayIndex(int axis, int iu, int iv) const { return iu + cells[uAxis(axis)] * iv; }
  double coordinate(int axis, int i) const { return box.min[axis] + (i + 0.5) * spacing[axis]; }
  // Origin of a ray: its two lattice coordinates, 0 along the ray.
  Vec3 rayOrigin(int axis, int iu, int iv) const;
  double cellArea(int axis) const { return spacing[uAxis(axis)] * spacing[vAxis(axis)]; }
  // Indices of the rays (lattice coordinates) of `axis` that lie within [lo, hi]; empty when first > last.
  std::array<int, 2> indexRange(int axis, double lo, double hi) const;
  double minSpacing() const { return spacing.minCoeff(); }
};

// Removes [cut.lo, cut.hi] from the spans; appends what was removed to `removed` (when given).
void subtractSpan(SpanList& spans, Span cut, SpanList* removed);
// Adds [add.lo, add.hi], merging with what it touches.
void addSpan(SpanList& spans, Span add);
bool spansContain(const SpanList& spans, double t);
double totalLength(const SpanList& spans);
// The spans of `a` outside every span of `b` (both sorted).
SpanList spanDifference(const SpanList& a, const SpanList& b);

}  // namespace art2part
