// Private to ray_visibility.cpp: the mesh as the ray caster sees it (float coordinates relative to the box centre,
// sample points, Morton order), the Embree scene built from it, and the walk over an occluding surface that lets
// most occlusion tests skip Embree.
#pragma once

#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part::raycast {

using Float3 = std::array<float, 3>;

constexpr int kMaxSamples = 7;

// A triangle as the walk over the surface reads it: its corners and neighbours in one place (one or two cache lines
// per step instead of five scattered reads).
struct WalkTriangle {
  Float3 corner[3];
  std::array<int, 3> across;  // position across edge k (corners k, k + 1); -1: boundary or non-manifold edge
};

// What the tracing threads share, computed once. Per-triangle data is stored in Morton order (position i holds
// triangle triangle[i]), so each direction walks it front to back and neighbouring rays start side by side. Embree
// sees the triangles in that order too: its primitive ids, the occluders and the walk all speak in positions, so
// the occluders of neighbouring rays sit close in memory.
struct Prepared {
  int samples = 1;                           // sample passes per direction
  std::vector<Float3> vertices;              // relative to the box centre: exactly what Embree sees
  std::vector<Triangle> corners;             // by triangle index, as in the mesh
  std::vector<WalkTriangle> walk;            // by position
  std::vector<int> triangle;                 // triangle index at each position
  std::vector<int> position;                 // position of each triangle index
  double lift = 0;                           // of every ray origin off its triangle, along the normal
  std::vector<double> nx, ny, nz;            // unit outward normals by position (zero when degenerate)
  std::vector<std::vector<Float3>> origins;  // origins[s][i]: sample s < kMaxSamples by position, relative to the
                                             // centre, lifted

  int size() const { return static_cast<int>(triangle.size()); }
};

// samples: 1..kMaxSamples.
Prepared prepare(const Mesh& mesh, int samples);

// A ray origin just inside edge k (corners k, k + 1) of the triangle at position i, a fraction `along` of the way
// from corner k, lifted like the samples.
Float3 edgeSample(const Prepared& p, int i, int k, double along);

// An occlusion ray from `origin` (relative to the box centre, like the scene) along d, to infinity, with the id the
// filter files its occluder under.
inline RTCRay occlusionRay(const Float3& origin, const Vec3& d, unsigned id) {
  RTCRay ray;
  ray.org_x = origin[0];
  ray.org_y = origin[1];
  ray.org_z = origin[2];
  ray.tnear = 0.0f;
  ray.dir_x = static_cast<float>(d.x());
  ray.dir_y = static_cast<float>(d.y());
  ray.dir_z = static_cast<float>(d.z());
  ray.time = 0.0f;
  ray.tfar = std::numeric_limits<float>::infinity();
  ray.mask = ~0u;
  ray.id = id;
  ray.flags = 0;
  return ray;
}

// Follows the ray over the surface from the triangle at position t, crossing to the neighbour beyond whichever edge
// the ray passes outside of, and returns the position of a triangle the ray clearly passes through in front of its
// origin, or -1 when the walk leaves the surface, turns back or takes too long. Any triangle returned is a real
// occluder.
int walkToHit(const Prepared& p, const Float3& origin, const Vec3& d, int t);

// An occlusion query's context, extended with where the filter writes the occluder of each ray (indexed by the
// ray's id). Embree hands the context to the filter as it was given.
struct TraceContext {
  RTCIntersectContext base;  // first member: the filter casts back from it
  int* occluder = nullptr;
  unsigned rays = 0;  // size of occluder: ids beyond it are ignored
};

// Owns the Embree device and the scene of the whole mesh (one triangle geometry, BVH built once). Occlusion
// queries must pass a TraceContext.
class EmbreeScene {
 public:
  explicit EmbreeScene(const Prepared& p);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene scene() const { return scene_; }

 private:
  void addTriangles(const Prepared& p);
  void check(const char* what) const;

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace art2part::raycast
