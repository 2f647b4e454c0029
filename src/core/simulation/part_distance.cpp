#include "art2part/simulation/part_distance.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace art2part {

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = va + vb + vc;
  if (!(std::abs(denominator) > 0)) return a;  // degenerate triangle
  return a + ab * (vb / denominator) + ac * (vc / denominator);
}

struct PartDistance::Scene {
  const Mesh* mesh = nullptr;
  Vec3 centre = Vec3::Zero();
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

namespace {

struct Nearest {
  const Mesh* mesh;
  Vec3 point;  // part frame
  double squared = std::numeric_limits<double>::infinity();
  int triangle = -1;
};

// Called by Embree for each triangle whose box lies within the query radius; shrinks the radius to the best so far.
bool visitTriangle(RTCPointQueryFunctionArguments* args) {
  auto* nearest = static_cast<Nearest*>(args->userPtr);
  const int t = static_cast<int>(args->primID);
  const Mesh& m = *nearest->mesh;
  const Vec3 q = closestPointOnTriangle(nearest->point, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2));
  const double squared = (q - nearest->point).squaredNorm();
  if (squared >= nearest->squared) return false;
  nearest->squared = squared;
  nearest->triangle = t;
  // Embree's boxes are floats: keep a hair of slack so a triangle as near as this one is not culled.
  args->query->radius = static_cast<float>(std::sqrt(squared) * (1 + 1e-6) + 1e-4);
  return true;
}

}  // namespace

PartDistance::PartDistance(const Mesh& mesh) : scene_(std::make_unique<Scene>()) {
  scene_->mesh = &mesh;
  scene_->centre = boundingBox(mesh).center();
  if (mesh.triangles.empty()) return;
  scene_->device = rtcNewDevice(nullptr);
  if (!scene_->device) throw std::runtime_error("Embree: cannot create a device");
  scene_->scene = rtcNewScene(scene_->device);
  RTCGeometry geometry = rtcNewGeometry(scene_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k] - scene_->centre[k]);
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                                 RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                                 mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_->scene);
  if (rtcGetDeviceError(scene_->device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the scene");
}

PartDistance::~PartDistance() {
  if (scene_->scene) rtcReleaseScene(scene_->scene);
  if (scene_->device) rtcReleaseDevice(scene_->device);
}

double PartDistance::distance(const Vec3& point, int* triangle, double max_distance) const {
  Nearest nearest{scene_->mesh, point};
  if (scene_->scene) {
    RTCPointQuery query;
    const Vec3 local = point - scene_->centre;
    query.x = static_cast<float>(local.x());
    query.y = static_cast<float>(local.y());
    query.z = static_cast<float>(local.z());
    query.time = 0.0f;
    query.radius = std::isfinite(max_distance) ? static_cast<float>(max_distance) : std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_->scene, &query, &context, visitTriangle, &nearest);
  }
  if (triangle) *triangle = nearest.triangle;
  return std::sqrt(nearest.squared);
}

}  // namespace art2part
