#include "art2part/roughing/tool_profiling.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <cmath>

#include "art2part/common/angles.h"

namespace art2part {

namespace {

constexpr int kMaxContacts = 64;
constexpr double kMaxStep = 10 * kPi / 180;

// One solid of the tool as FCL sees it: a cylinder from h0 to h1 above the tip, or a sphere centred at h0.
struct ToolBody {
  bool sphere = false;
  double h0 = 0, h1 = 0, radius = 0;
  ToolZone zone = ToolZone::Flutes;
};

std::vector<ToolBody> toolBodies(const Tool& tool, double flute_margin, double body_margin) {
  std::vector<ToolBody> bodies;
  const double r = tool.diameter / 2;
  // Below the tip the flutes are grown by half the margin only: a tip placed the allowance over a floor touches
  // nothing (the simulation judges gouges to 0.01 mm).
  if (tool.type == ToolType::Ball) {
    bodies.push_back({true, r, r, r + flute_margin, ToolZone::Flutes});
    if (tool.flute_length > r) bodies.push_back({false, r, tool.flute_length, r + flute_margin, ToolZone::Flutes});
  } else {
    bodies.push_back({false, -0.5 * flute_margin, tool.flute_length, r + flute_margin, ToolZone::Flutes});
  }
  if (tool.stickout > tool.flute_length)
    bodies.push_back({false, tool.flute_length, tool.stickout, tool.shank_diameter / 2 + body_margin, ToolZone::Shank});
  double from = tool.stickout;
  for (const HolderStep& step : tool.holder) {
    bodies.push_back({false, from, from + step.length, step.diameter / 2 + body_margin, ToolZone::Holder});
    from += step.length;
  }
  return bodies;
}

// The rotation taking +z to `axis`.
Eigen::Matrix3d alignZ(const Vec3& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis.normalized()).toRotationMatrix();
}

// How far along its axis the tool is pushed so that its lowest point along `up` stays at the machining point: a
// tilted end face dips (r - rc) sin(theta) + rc (1 - cos(theta)) below its tip (rc the corner radius: 0 flat, r ball),
// r grown by the margin the flutes keep.
double pushAlongAxis(const Tool& tool, double margin, const Vec3& axis, const Vec3& up) {
  const double c = std::clamp(axis.dot(up), 1e-3, 1.0), s = std::sqrt(std::max(0.0, 1 - c * c));
  const double r = tool.diameter / 2 + margin;
  const double rc = tool.type == ToolType::Ball ? r : (tool.type == ToolType::Bull ? tool.corner_radius : 0.0);
  return ((r - rc) * s + rc * (1 - c)) / c;
}

}  // namespace

struct PartCollider::Model {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> tree;
  std::unique_ptr<fcl::CollisionObjectd> object;
  std::vector<Vec3> normals;  // outward, by triangle
};

PartCollider::PartCollider(const Mesh& part) : model_(std::make_unique<Model>()) {
  model_->tree = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> points(part.vertices.begin(), part.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(part.triangles.size());
  for (const Triangle& t : part.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  model_->tree->beginModel(static_cast<int>(triangles.size()), static_cast<int>(points.size()));
  model_->tree->addSubModel(points, triangles);
  model_->tree->endModel();
  model_->object = std::make_unique<fcl::CollisionObjectd>(model_->tree, fcl::Transform3d::Identity());
  for (int t = 0; t < part.triangleCount(); ++t) model_->normals.push_back(triangleNormal(part, t));
}

PartCollider::~PartCollider() = default;

bool PartCollider::toolClear(const Tool& tool, const ToolPose& pose, double flute_margin, double body_margin,
                             std::vector<ProfileContact>* contacts) const {
  const Vec3 axis = pose.axis.normalized();
  const Eigen::Matrix3d rotation = alignZ(axis);
  bool clear = true;
  for (const ToolBody& body : toolBodies(tool, flute_margin, body_margin)) {
    std::shared_ptr<fcl::CollisionGeometryd> shape;
    fcl::Transform3d place = fcl::Transform3d::Identity();
    place.linear() = rotation;
    if (body.sphere) {
      shape = std::make_shared<fcl::Sphered>(body.radius);
      place.translation() = pose.tip + body.h0 * axis;
    } else {
      if (body.h1 <= body.h0) continue;
      shape = std::make_shared<fcl::Cylinderd>(body.radius, body.h1 - body.h0);
      place.translation() = pose.tip + 0.5 * (body.h0 + body.h1) * axis;
    }
    const fcl::CollisionObjectd solid(shape, place);
    fcl::CollisionRequestd request(contacts ? kMaxContacts : 1, contacts != nullptr);
    fcl::CollisionResultd result;
    fcl::collide(&solid, model_->object.get(), request, result);
    if (!result.isCollision()) continue;
    clear = false;
    if (!contacts) return false;
    for (std::size_t i = 0; i < result.numContacts(); ++i) {
      const fcl::Contactd& c = result.getContact(i);
      ProfileContact contact;
      contact.point = c.pos;
      const Vec3 offset = c.pos - pose.tip;
      contact.height = offset.dot(axis);
      const double radial = (offset - contact.height * axis).norm();
      // FCL's own normal comes from the penetration's direction, which has either sense once a triangle is deep
      // in the tool; the triangle's outward normal says which way the part pushes.
      const auto triangle = c.o1 == model_->tree.get() ? c.b1 : (c.o2 == model_->tree.get() ? c.b2 : -1);
      contact.normal = triangle >= 0 && triangle < static_cast<std::intptr_t>(model_->normals.size())
                           ? model_->normals[triangle]
                           : Vec3(-c.normal);
      contact.depth = c.penetration_depth > 0 ? c.penetration_depth
                                              : (body.sphere ? body.radius - (c.pos - place.translation()).norm()
                                                             : body.radius - radial);
      contact.zone = body.zone;
      contacts->push_back(contact);
    }
  }
  return clear;
}

Posture profileTool(const PartCollider& part, const std::vector<const Tool*>& tools, const ToolPose& proposed,
                    const Vec3& reach_axis, const ProfileOptions& options) {
  const double cos_reach = std::cos(options.max_tilt_deg * kPi / 180);
  const Vec3 reach = reach_axis.normalized();
  const int zones = std::max(2, options.zones + options.zones % 2);
  for (int t = 0; t < static_cast<int>(tools.size()); ++t) {
    const Tool& tool = *tools[t];
    Vec3 axis = proposed.axis.normalized();
    for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
      if (axis.dot(reach) < cos_reach - 1e-12) break;  // tilted beyond the machine
      const Vec3 tip = proposed.tip + pushAlongAxis(tool, options.flute_margin, axis, reach) * axis;
      std::vector<ProfileContact> contacts;
      if (part.toolClear(tool, {tip, axis}, options.flute_margin, options.body_margin, &contacts))
        return {true, t, {tip, axis}, iteration};
      // Zones round the axis: the deepest penetration of each, and the direction from the axis to it.
      const Vec3 u = axis.unitOrthogonal(), w = axis.cross(u);
      std::vector<double> depth(zones, 0.0), lever(zones, 1.0);
      std::vector<Vec3> side(zones, Vec3::Zero());
      for (const ProfileContact& c : contacts) {
        // The side of the tool the part presses on: against the part's outward normal, across the axis. (The offset
        // of the contact point from the axis would mislead once the axis itself has entered the part.)
        const Vec3 across = -(c.normal - c.normal.dot(axis) * axis);
        if (across.norm() < 0.3) continue;  // a face across the axis (a floor, a ceiling) gives no side to leave
        const double azimuth = std::atan2(across.dot(w), across.dot(u));
        const int z = static_cast<int>(std::floor((azimuth + kPi) / (2 * kPi) * zones)) % zones;
        if (c.depth > depth[z]) {
          depth[z] = std::max(c.depth, 0.05);
          lever[z] = std::max({c.height, 0.5 * tool.diameter, 1.0});
          side[z] = across.normalized();
        }
      }
      bool trapped = false, any = false;
      for (int z = 0; z < zones; ++z) {
        any = any || depth[z] > 0;
        trapped = trapped || (depth[z] > 0 && depth[(z + zones / 2) % zones] > 0);
      }
      if (trapped || !any) break;  // no escape by tilting: a smaller tool
      Vec3 tilted = axis;
      // Each zone asks for atan(penetration / lever) (and half a degree), at most 10 degrees a step: penetration
      // depths of triangles deep inside the tool are rough.
      for (int z = 0; z < zones; ++z)
        if (depth[z] > 0)
          tilted -= std::tan(std::min(std::atan2(depth[z], lever[z]), kMaxStep) + 0.5 * kPi / 180) * side[z];
      axis = tilted.normalized();
    }
  }
  return {};
}

}  // namespace art2part
