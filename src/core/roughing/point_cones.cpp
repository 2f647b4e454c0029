#include "art2part/roughing/point_cones.h"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>

namespace art2part {

namespace {

// Embree works in float: coordinates are taken relative to the part's box centre, where float keeps ~0.03 um on a
// 500 mm part.
Vec3 boxCentre(const Mesh& mesh) {
  const Box box = boundingBox(mesh);
  return mesh.vertices.empty() ? Vec3::Zero() : Vec3(0.5 * (box.min + box.max));
}

// Rays start this far from the point (the point itself may lie on a face: a floor under the allowance).
constexpr float kStart = 1e-4f;

}  // namespace

PointCones::PointCones(const Mesh& part, const DirectionSet& directions) : directions_(directions) {
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error("Embree: cannot create a device");
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips between two occluding triangles
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const Vec3 centre = boxCentre(part);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), part.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), part.triangles.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    throw std::runtime_error("Embree: cannot allocate the mesh buffers");
  }
  for (const Vec3& v : part.vertices)
    for (int k = 0; k < 3; ++k) *vertices++ = static_cast<float>(v[k] - centre[k]);
  for (const Triangle& t : part.triangles)
    for (int k = 0; k < 3; ++k) *indices++ = static_cast<unsigned>(t[k]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  device_ = device;
  scene_ = scene;
  centre_ = centre;
}

PointCones::~PointCones() {
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

bool PointCones::escapes(const Vec3& p, const Vec3& d) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  ray.org_x = static_cast<float>(p.x() - centre_.x());
  ray.org_y = static_cast<float>(p.y() - centre_.y());
  ray.org_z = static_cast<float>(p.z() - centre_.z());
  ray.dir_x = static_cast<float>(d.x());
  ray.dir_y = static_cast<float>(d.y());
  ray.dir_z = static_cast<float>(d.z());
  ray.tnear = kStart;
  ray.tfar = std::numeric_limits<float>::infinity();
  ray.time = 0;
  ray.mask = 0xffffffffu;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(static_cast<RTCScene>(scene_), &context, &ray);
  return ray.tfar >= 0;  // Embree sets tfar to -inf on a hit
}

Cone PointCones::coneAt(const Vec3& p, const Cone& among) const {
  Cone cone(among.size(), 0);
  std::size_t rays = 0;
  for (std::size_t w = 0; w < among.size(); ++w)
    for (std::uint64_t bits = among[w]; bits; bits &= bits - 1) {
      const int d = static_cast<int>(64 * w) + __builtin_ctzll(bits);
      if (d >= directions_.size()) break;
      ++rays;
      if (escapes(p, directions_.directions[d])) cone[w] |= std::uint64_t(1) << (d & 63);
    }
  rays_ += rays;
  return cone;
}

}  // namespace art2part
