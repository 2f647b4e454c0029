// Volume visibility (thesis 3.2.5, Algorithm 3): a voxel grid of the stock minus the part (the delta volume), each
// voxel with the set of sampled directions along which a straight line from it escapes the part.
//
// Where the thesis casts rays from visible surface points and tags the voxels they cross, we test every voxel
// against a height map per direction (a CPU shadow map): for direction d, an orthographic grid of pixels
// perpendicular to d holds the largest p . d of the part over each pixel (conservative: a triangle that touches a
// pixel at all raises it to the largest height the triangle can reach inside that pixel). A voxel centre x sees d
// when x . d + tolerance >= H_d(pixel of x), tolerance ~0 (see the option). Cost per direction
// O(triangles + pixels + voxels).
//
// Storage: the per-voxel cones are interned. A voxel holds a 32-bit index into a table of distinct cones; voxels
// inside the part hold kInsidePart. Far from the part many voxels share a cone, but near it cones hardly repeat
// (86-95% of delta voxels had a distinct cone on ANC101 at 2 mm and CTC 1 at 4 mm), so this only halves the memory
// of a bitset per voxel (D / 8 bytes each); differences between neighbouring voxels would store far less.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/visibility/cones.h"

namespace art2part {

// Voxels of size `voxel` mm; voxel (i, j, k) is the cube [origin + (i, j, k) voxel, origin + (i+1, j+1, k+1) voxel],
// index i + nx (j + ny k). Part frame.
struct VoxelGrid {
  Vec3 origin = Vec3::Zero();
  double voxel = 1.0;
  int nx = 0, ny = 0, nz = 0;

  std::size_t size() const { return static_cast<std::size_t>(nx) * ny * nz; }
  int index(int i, int j, int k) const { return i + nx * (j + ny * k); }
  std::array<int, 3> cell(int v) const { return {v % nx, (v / nx) % ny, v / (nx * ny)}; }
  Vec3 centre(int i, int j, int k) const { return origin + voxel * Vec3(i + 0.5, j + 0.5, k + 0.5); }
  Vec3 centre(int v) const {
    const auto c = cell(v);
    return centre(c[0], c[1], c[2]);
  }
  // The voxel containing p, or -1 outside the grid.
  int voxelAt(const Vec3& p) const;
};

struct VolumeVisibility {
  static constexpr std::uint32_t kInsidePart = 0xffffffffu;

  VoxelGrid grid;
  int directions = 0;
  std::vector<std::uint32_t> cone_of_voxel;  // index into the cone table, or kInsidePart
  // The distinct cones, in order of first voxel, flat: cone c is words [c * words_per_cone, (c + 1) * words_per_cone)
  // in the Cone bit layout (one vector per cone would add 24 bytes of bookkeeping to each).
  int words_per_cone = 0;
  std::vector<std::uint64_t> cone_words;

  std::size_t coneCount() const { return words_per_cone ? cone_words.size() / words_per_cone : 0; }
  Cone cone(std::uint32_t c) const {
    const auto* w = cone_words.data() + std::size_t(c) * words_per_cone;
    return Cone(w, w + words_per_cone);
  }
  bool outsidePart(int v) const { return cone_of_voxel[v] != kInsidePart; }
  bool reachable(int v, int d) const {
    const std::uint32_t c = cone_of_voxel[v];
    return c != kInsidePart &&
           (cone_words[std::size_t(c) * words_per_cone + (d >> 6)] >> (d & 63) & 1u);
  }
  std::size_t deltaVoxels() const;  // voxels outside the part
  std::size_t bytes() const;        // memory held by the result (index + cone table)
};

struct VolumeVisibilityOptions {
  double voxel_size = 1.0;  // mm
  double margin = 5.0;      // stock = part bounding box grown by this on every side, mm
  // Height-map pixel size as a fraction of the voxel. The conservative coverage over-blocks voxels within about
  // (pixel diagonal) of a surface seen at grazing angles; half a voxel keeps that inside one voxel.
  double pixel_ratio = 0.5;
  // A voxel sees d when its centre moved this far along d (mm) clears the height map; < 0: a thousandth of a voxel,
  // which only absorbs the rounding of heights to float. Why not half a voxel: a voxel whose centre lies delta < tol
  // from a face would then see *into* that face (every d within acos(delta / tol) of the inward normal), a false
  // "reachable" that a tool path would trust. With ~0 the answer is one-sided: a voxel reported reachable along d is
  // (up to the float rounding) really reachable from its centre; the errors are false "blocked" for centres within
  // one pixel diagonal of a surface (a plane face seen at angle theta from its normal over-blocks centres closer
  // than diagonal * sin theta), i.e. within 0.36 voxel at the default pixel ratio.
  double tolerance = -1.0;
  int threads = 0;                  // 0 = hardware threads
  double max_voxels = 2e8;          // beyond this the grid is refused (InputError)
};

// The stock grid: part bounding box plus margin, centred on the box. Throws InputError for a voxel size <= 0 or a
// grid of more than options.max_voxels voxels.
VoxelGrid stockGrid(const Mesh& mesh, const VolumeVisibilityOptions& options = {});

// 1 for voxels whose centre lies outside the part: the winding number along a +z ray per (x, y) column. Only a
// closed mesh has a meaningful inside; through a hole in an open mesh a column may come out inverted.
std::vector<char> voxelsOutsidePart(const Mesh& mesh, const VoxelGrid& grid);

VolumeVisibility volumeVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                                  const VolumeVisibilityOptions& options = {});

}  // namespace art2part
