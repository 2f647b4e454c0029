#include "ray_scene.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace art2part::raycast {

namespace {

// Barycentric weights of the sample points: the centroid first (it decides most triangles alone), then points
// 60% of the way towards each corner, then 60% of the way towards each edge midpoint. None lies on an edge, so a
// ray from a sample never grazes a face that meets the triangle along an edge.
constexpr double kSampleWeights[kMaxSamples][3] = {
    {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.6, 0.2, 0.2}, {0.2, 0.6, 0.2}, {0.2, 0.2, 0.6},
    {0.4, 0.4, 0.2},             {0.2, 0.4, 0.4}, {0.4, 0.2, 0.4}};

// Ray origins are lifted off their triangle along its normal by this fraction of the box diagonal. Floats round
// coordinates (taken relative to the box centre) by about 3e-8 of the diagonal, so 1e-6 keeps the origin strictly
// above the triangle's own plane, and above coplanar neighbours, for any direction with n . d > 0, however grazing.
// (An offset along d instead would lift the origin by only eps * (n . d), nothing for grazing directions.)
constexpr double kLiftFraction = 1e-6;

// Edge samples sit this fraction of the way from the edge towards the opposite corner: inside the triangle, so their
// rays do not graze the neighbour across the edge, yet close enough to see what the neighbour sees.
constexpr double kEdgeInset = 0.01;

// The walk accepts a triangle only when the ray passes this far (in barycentric terms) inside it; rays near an edge
// go to Embree, whose watertight test settles them.
constexpr double kInsideMargin = 1e-6;

// Triangles the walk visits before giving up: the ray usually lands within a few triangles of the last occluder.
constexpr int kMaxWalk = 8;

std::uint32_t spreadBits10(std::uint32_t v) {
  v &= 0x3ff;
  v = (v | (v << 16)) & 0x030000ff;
  v = (v | (v << 8)) & 0x0300f00f;
  v = (v | (v << 4)) & 0x030c30c3;
  v = (v | (v << 2)) & 0x09249249;
  return v;
}

// Morton code of a point of the unit cube (10 bits per axis): nearby points, nearby codes.
std::uint32_t mortonCode(const Vec3& unit) {
  std::uint32_t code = 0;
  for (int k = 0; k < 3; ++k)
    code |= spreadBits10(static_cast<std::uint32_t>(std::clamp(unit[k] * 1023.0, 0.0, 1023.0))) << k;
  return code;
}

Vec3 toVec(const Float3& f) { return Vec3(f[0], f[1], f[2]); }

// Pairs the triangles sharing each edge (by vertex indices). Edges with one triangle or more than two stay -1: the
// walk stops there and Embree decides.
std::vector<std::array<int, 3>> edgeNeighbours(const std::vector<Triangle>& triangles) {
  struct EdgeRef {
    std::uint64_t key;
    int triangle, edge;
  };
  std::vector<EdgeRef> edges;
  edges.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(triangles[t][k]);
      const auto b = static_cast<std::uint32_t>(triangles[t][(k + 1) % 3]);
      if (a != b) edges.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), int(t), k});
    }
  std::sort(edges.begin(), edges.end(), [](const EdgeRef& x, const EdgeRef& y) { return x.key < y.key; });
  std::vector<std::array<int, 3>> across(triangles.size(), {-1, -1, -1});
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 2) {
      across[edges[i].triangle][edges[i].edge] = edges[i + 1].triangle;
      across[edges[i + 1].triangle][edges[i + 1].edge] = edges[i].triangle;
    }
    i = j;
  }
  return across;
}

// Called for the hit that ends an occlusion query; accepts it (leaves valid alone) and notes who occluded.
void recordOccluder(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const TraceContext*>(args->context);
  for (unsigned k = 0; k < args->N; ++k) {
    const unsigned id = RTCRayN_id(args->ray, args->N, k);
    if (args->valid[k] == -1 && id < context->rays)
      context->occluder[id] = static_cast<int>(RTCHitN_primID(args->hit, args->N, k));
  }
}

}  // namespace

Prepared prepare(const Mesh& mesh, int samples) {
  const Box box = boundingBox(mesh);
  const Vec3 centre = box.center(), size = box.size().cwiseMax(1e-300);
  const double lift = kLiftFraction * box.diagonal();
  Prepared p;
  p.samples = samples;
  p.corners = mesh.triangles;
  // Relative to the box centre in double first: parts far from the origin keep their float precision.
  for (const Vec3& v : mesh.vertices) {
    const Vec3 r = v - centre;
    p.vertices.push_back({float(r.x()), float(r.y()), float(r.z())});
  }
  const int n = mesh.triangleCount();
  std::vector<std::uint32_t> code(n);
  for (int t = 0; t < n; ++t) code[t] = mortonCode((triangleCentroid(mesh, t) - box.min).cwiseQuotient(size));
  p.triangle.resize(n);
  std::iota(p.triangle.begin(), p.triangle.end(), 0);
  std::stable_sort(p.triangle.begin(), p.triangle.end(), [&](int a, int b) { return code[a] < code[b]; });
  p.position.resize(n);
  for (int i = 0; i < n; ++i) p.position[p.triangle[i]] = i;
  const std::vector<std::array<int, 3>> across = edgeNeighbours(mesh.triangles);
  p.walk.resize(n);
  for (int i = 0; i < n; ++i) {
    const int t = p.triangle[i];
    for (int k = 0; k < 3; ++k) {
      p.walk[i].corner[k] = p.vertices[mesh.triangles[t][k]];
      p.walk[i].across[k] = across[t][k] < 0 ? -1 : p.position[across[t][k]];
    }
  }
  p.lift = lift;

  p.nx.resize(n);
  p.ny.resize(n);
  p.nz.resize(n);
  p.origins.assign(kMaxSamples, std::vector<Float3>(n));  // every sample: the rescue pass uses them all
  for (int i = 0; i < n; ++i) {
    const int t = p.triangle[i];
    const Vec3 normal = triangleNormal(mesh, t);
    p.nx[i] = normal.x();
    p.ny[i] = normal.y();
    p.nz[i] = normal.z();
    const Vec3 a = mesh.corner(t, 0) - centre, b = mesh.corner(t, 1) - centre, c = mesh.corner(t, 2) - centre;
    for (int s = 0; s < kMaxSamples; ++s) {
      const double* w = kSampleWeights[s];
      const Vec3 o = w[0] * a + w[1] * b + w[2] * c + lift * normal;
      p.origins[s][i] = {float(o.x()), float(o.y()), float(o.z())};
    }
  }
  return p;
}

Float3 edgeSample(const Prepared& p, int i, int k, double along) {
  const WalkTriangle& triangle = p.walk[i];
  const Vec3 a = toVec(triangle.corner[k]), b = toVec(triangle.corner[(k + 1) % 3]);
  const Vec3 opposite = toVec(triangle.corner[(k + 2) % 3]);
  const Vec3 normal(p.nx[i], p.ny[i], p.nz[i]);
  const Vec3 o = (1 - kEdgeInset) * (a + along * (b - a)) + kEdgeInset * opposite + p.lift * normal;
  return {float(o.x()), float(o.y()), float(o.z())};
}

int walkToHit(const Prepared& p, const Float3& origin, const Vec3& d, int t) {
  const Vec3 o = toVec(origin);
  int previous = -1;
  for (int step = 0; step < kMaxWalk && t >= 0; ++step) {
    // Moller-Trumbore, in double on the very float coordinates Embree uses. w are the barycentric weights of the
    // point where the ray meets the triangle's plane, scaled by |det| (no division: it sits on the critical path).
    const WalkTriangle& triangle = p.walk[t];
    const Vec3 a = toVec(triangle.corner[0]);
    const Vec3 e1 = toVec(triangle.corner[1]) - a, e2 = toVec(triangle.corner[2]) - a;
    const Vec3 q = d.cross(e2);
    const double det = e1.dot(q);
    if (det == 0.0) return -1;  // the ray runs along the plane
    const double sign = det > 0.0 ? 1.0 : -1.0, scale = sign * det;
    const Vec3 s = o - a, r = s.cross(e1);
    const double u = sign * s.dot(q), v = sign * d.dot(r);
    const double w[3] = {scale - u - v, u, v};
    const int k = w[0] < w[1] ? (w[0] < w[2] ? 0 : 2) : (w[1] < w[2] ? 1 : 2);
    if (w[k] >= kInsideMargin * scale) return sign * e2.dot(r) > 0.0 ? t : -1;
    // Outside beyond the edge opposite corner k, which is edge k + 1 (corners k + 1, k + 2).
    const int next = triangle.across[(k + 1) % 3];
    if (next == previous) return -1;  // bouncing across an edge the ray passes too close to
    previous = t;
    t = next;
  }
  return -1;
}

EmbreeScene::EmbreeScene(const Prepared& p) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree: cannot create a device");
  scene_ = rtcNewScene(device_);
  // Robust mode makes the triangle test watertight: a ray crossing the shared edge of two occluding triangles hits
  // one of them instead of slipping through the crack and counting as a clear view.
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  addTriangles(p);
  rtcCommitScene(scene_);
  check("building the scene");
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeScene::check(const char* what) const {
  const RTCError error = rtcGetDeviceError(device_);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: error " + std::to_string(int(error)) + " " + what);
}

void EmbreeScene::addTriangles(const Prepared& p) {
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  rtcSetGeometryOccludedFilterFunction(geometry, recordOccluder);
  // Embree owns these buffers and pads them as its SIMD loads need.
  auto* vertices = static_cast<Float3*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                sizeof(Float3), p.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), p.corners.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    check("allocating the mesh buffers");
    throw std::runtime_error("Embree: cannot allocate the mesh buffers");
  }
  std::copy(p.vertices.begin(), p.vertices.end(), vertices);
  for (int t : p.triangle)  // in position order: primitive ids are positions
    for (int k = 0; k < 3; ++k) *indices++ = static_cast<unsigned>(p.corners[t][k]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);  // the scene keeps its own reference
}

}  // namespace art2part::raycast
