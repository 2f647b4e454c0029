// Surface finishing (surface_finishing.h): the stepover from the scallop, the faces' curvature, the CL map and its
// regions, and the 3-axis operation.
#include "art2part/finishing/surface_finishing.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "art2part/roughing/shadow.h"
#include "surface_plan.h"

namespace art2part {

using surface::kInf;

double scallopStepover(double tool_radius, double scallop, double surface_radius) {
  const double R = tool_radius, h = scallop;
  if (!(R > 0) || !std::isfinite(R)) throw InputError("scallop stepover: the tool radius must be positive");
  if (!(h > 0) || !std::isfinite(h)) throw InputError("scallop stepover: the scallop must be positive");
  if (std::isnan(surface_radius) || surface_radius == 0)
    throw InputError("scallop stepover: the surface radius must be non-zero (infinity for a flat)");
  if (h >= R) return 2 * R;
  const double k = 2 * R * h - h * h;
  if (std::isinf(surface_radius)) return 2 * std::sqrt(k);
  const double rho = std::abs(surface_radius);
  double D, x;
  if (surface_radius > 0) {
    D = rho + R;
    x = rho + h;
  } else {
    if (!(rho > R))
      throw InputError("scallop stepover: a concave radius of " + std::to_string(rho) +
                       " mm does not take a tool of radius " + std::to_string(R) + " mm");
    D = rho - R;
    x = rho - h;
  }
  // 1 - cos(phi / 2) = k / (2 x D) = 2 sin^2(phi / 4): stable for any radius.
  const double phi = 4 * std::asin(std::min(1.0, std::sqrt(k / (4 * x * D))));
  return D * phi;
}

namespace surface {

std::vector<double> faceConcaveRadii(const Part& part) {
  std::vector<double> out(part.faces.size(), kInf);
  // A cone's radius of curvature across it: the distance to the axis over cos(half angle), least at its nearest point.
  std::vector<double> cone_nearest(part.faces.size(), kInf);
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {
    const int f = part.triangle_face[t];
    if (f < 0 || part.faces[f].type != SurfaceType::Cone) continue;
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = part.mesh.corner(t, k) - part.faces[f].point;
      cone_nearest[f] = std::min(cone_nearest[f], (d - d.dot(part.faces[f].axis) * part.faces[f].axis).norm());
    }
  }
  for (std::size_t f = 0; f < part.faces.size(); ++f) {
    const Face& face = part.faces[f];
    switch (face.type) {
      case SurfaceType::Sphere:
      case SurfaceType::Cylinder:
        if (face.concave) out[f] = face.radius;
        break;
      case SurfaceType::Cone:
        if (face.concave) out[f] = cone_nearest[f] / std::cos(face.half_angle);
        break;
      case SurfaceType::Torus:
        // Across the tube the minor radius (concave for a fillet); around the axis at least |major - minor|, concave on
        // the inner side of the tube whatever the flag says: the least of those that may be concave.
        out[f] = std::abs(face.radius - face.minor_radius);
        if (face.concave) out[f] = std::min(out[f], face.minor_radius);
        break;
      case SurfaceType::Plane:
      case SurfaceType::Other: break;
    }
    if (!(out[f] > 0)) out[f] = kInf;
  }
  return out;
}

std::vector<int> checkedFaces(const Part& part, const std::vector<int>& faces) {
  if (faces.empty()) throw InputError("surface finishing: no faces given");
  std::vector<int> out = faces;
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  for (int f : out)
    if (f < 0 || f >= static_cast<int>(part.faces.size()))
      throw InputError("surface finishing: face " + std::to_string(f) + " is not a face of the part (it has " +
                       std::to_string(part.faces.size()) + ")");
  if (part.triangle_face.size() != part.mesh.triangles.size())
    throw InputError("surface finishing: the part's triangle-face map does not match its mesh");
  return out;
}

void checkOptions(const SurfaceFinishingOptions& o) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) throw InputError(std::string("surface finishing: ") + name + " must be positive");
  };
  auto nonNegative = [](double v, const char* name) {
    if (!(v >= 0) || !std::isfinite(v)) throw InputError(std::string("surface finishing: ") + name + " must be >= 0");
  };
  positive(o.scallop, "scallop");
  positive(o.chordal_tolerance, "chordal_tolerance");
  if (!(o.steep_angle_deg > kSteepOverlapDeg && o.steep_angle_deg < 90 - kSteepOverlapDeg))
    throw InputError("surface finishing: steep_angle_deg must lie between " + std::to_string(kSteepOverlapDeg) +
                     " and " + std::to_string(90 - kSteepOverlapDeg));
  nonNegative(o.sample_step, "sample_step");
  nonNegative(o.map_pitch, "map_pitch");
  nonNegative(o.region_margin, "region_margin");
  nonNegative(o.skin, "skin");
  nonNegative(o.holder_margin, "holder_margin");
  nonNegative(o.clearance, "clearance");
  nonNegative(o.link_margin, "link_margin");
  nonNegative(o.feed_link_mm, "feed_link_mm");
  nonNegative(o.short_link_mm, "short_link_mm");
  if (!(o.max_tilt_deg >= 0 && o.max_tilt_deg < 90)) throw InputError("surface finishing: max_tilt_deg must lie in [0, 90)");
  positive(o.tilt_step_deg, "tilt_step_deg");
  positive(o.max_tilt_rate_deg_mm, "max_tilt_rate_deg_mm");
}

}  // namespace surface

SurfaceFinishingResult finishSurfaces3Axis(const Part& part, const std::vector<int>& faces, const SetupFrame& frame,
                                           const Tool& tool, int setup, const SurfaceFinishingOptions& options,
                                           const std::vector<SlabState>& stock_beyond) {
  const auto start = std::chrono::steady_clock::now();
  SurfaceFinishingResult result;
  surface::Plan plan = surface::planPasses(part, faces, frame, tool, options, true, stock_beyond, result);
  if (!plan.ordered.passes.empty()) {
    const surface::Linked linked = surface::link3Axis(*plan.ctx, plan.ordered.passes, plan.short_link,
                                                      options.link_margin, plan.clearance_z);
    result.retracts = linked.retracts;
    result.path.reserve(linked.moves.size());
    for (const surface::Move& m : linked.moves) {
      CutterLocation c;
      c.setup = setup;
      c.tool = tool.id;
      c.move = m.kind;
      c.tip = fromFrame(m.p, frame);
      c.axis = frame.z;
      result.path.push_back(c);
    }
  }
  result.drops = plan.ctx ? plan.ctx->drops.load() : 0;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace art2part
