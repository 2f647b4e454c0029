// Strategy, setup and direction per face (face_assignment.h).
#include "art2part/finishing/face_assignment.h"

#include <algorithm>
#include <cmath>

#include "art2part/common/angles.h"
#include "art2part/common/number_text.h"
#include "art2part/finishing/admissible.h"
#include "art2part/visibility/cones.h"

namespace art2part {

namespace {

constexpr double kSameDirection = 0.01 * kPi / 180;  // a sampled direction this close is the face's own
constexpr std::size_t kSurfaceChoices = 3;            // surface finishing is offered from this many setups at most

// A direction the plan offers: a setup's, or in 5-axis mode a face's own sampled direction within a setup's tilt.
struct Offer {
  int setup = -1;
  int index = -1;  // into visibility.directions
  Vec3 d = Vec3::UnitZ();
};

// The offers for a face's own direction `d`: every setup direction within the tilt (5-axis), the nearest first.
std::vector<Offer> ownDirectionOffers(const SetupPlan& setups, const DirectionSet& directions, const Vec3& d,
                                      const FinishingOptions& options) {
  std::vector<Offer> out;
  if (options.mode != MachineMode::FiveAxis) return out;
  const int index = sampledDirection(directions, d, kSameDirection);
  if (index < 0) return out;
  const double tilt = setups.max_tilt_deg * kPi / 180;
  for (int k = 0; k < static_cast<int>(setups.setups.size()); ++k)
    if (std::acos(std::clamp(setups.setups[k].frame.z.dot(d), -1.0, 1.0)) <= tilt + 1e-9) out.push_back({k, index, d});
  std::sort(out.begin(), out.end(), [&](const Offer& a, const Offer& b) {
    return setups.setups[a.setup].frame.z.dot(d) > setups.setups[b.setup].frame.z.dot(d);
  });
  return out;
}

double leastDot(const AdmissibleSet& surface, const Vec3& d) {
  double least = 1;
  for (const Vec3& n : surface.normals) least = std::min(least, n.dot(d));
  return least;
}

std::string mm(double v) { return numberText(v, v < 10 ? 2 : 3) + " mm"; }

}  // namespace

std::vector<FaceAssignment> assignFaces(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                        const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods,
                                        double longest_flutes, const FinishingOptions& options) {
  if (visibility.map.triangles() != part.mesh.triangleCount())
    throw InputError("finishing: the visibility map has " + std::to_string(visibility.map.triangles()) +
                     " triangles but the part has " + std::to_string(part.mesh.triangleCount()));
  const DirectionSet& directions = visibility.directions;
  const double tolerance = options.planar.square_angle_deg * kPi / 180;
  const std::vector<std::vector<int>> triangles = faceTriangles(part);
  std::vector<Offer> setup_offers;
  for (int k = 0; k < static_cast<int>(setups.setups.size()); ++k)
    setup_offers.push_back({k, setups.setups[k].direction, setups.setups[k].frame.z});
  // Faces a drill or a helix makes: each hole's bore and bottom (a counterbore or countersink is milled as any face).
  std::vector<int> hole_of(part.faces.size(), -1);
  for (int h = 0; h < static_cast<int>(holes.size()); ++h)
    if (h < static_cast<int>(methods.size()) && methods[h].method != HoleMethod::None)
      for (int f : holes[h].bore_faces)
        if (f >= 0 && f < static_cast<int>(hole_of.size())) hole_of[f] = h;

  std::vector<FaceAssignment> out(part.faces.size());
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    FaceAssignment& a = out[f];
    a.face = f;
    const std::vector<int>& tris = triangles[f];
    if (tris.empty()) {
      a.reason = "no triangles";
      continue;
    }
    const Cone accessible = commonCone(visibility.map, tris);
    auto sees = [&](const Offer& o) { return o.index >= 0 && o.index < directions.size() && coneHas(accessible, o.index); };
    auto add = [&](FinishingKind kind, const Offer& o, double depth, bool whole, const std::string& note) {
      for (const FinishingChoice& c : a.choices)
        if (c.kind == kind && c.setup == o.setup && c.direction.dot(o.d) > std::cos(1e-6)) return;
      a.choices.push_back({kind, o.setup, o.d, -1, depth, whole, note});
    };
    std::string surface_note;
    // Holes: along the hole's axis out of it, or for a through hole out of its other end.
    if (hole_of[f] >= 0) {
      const Hole& hole = holes[hole_of[f]];
      std::vector<Offer> offers;
      const double cos_axis = std::cos(options.holes.axis_tolerance_deg * kPi / 180);
      for (const Offer& o : setup_offers)
        if (o.d.dot(hole.axis) >= cos_axis || (hole.bottom == HoleBottom::Through && -o.d.dot(hole.axis) >= cos_axis))
          offers.push_back(o);
      for (const Offer& o : ownDirectionOffers(setups, directions, hole.axis, options)) offers.push_back(o);
      if (!offers.empty()) {
        // A hole's bottom faces may be unseen by the sampled visibility: the axis rules.
        const Offer& o = offers.front();
        a.choices.push_back({methods[hole_of[f]].method == HoleMethod::Drill ? FinishingKind::Drill : FinishingKind::Helix,
                             o.setup, o.d, hole_of[f], 0, sees(o), ""});
      } else {
        surface_note = "its hole's axis is no setup direction";
      }
    }
    const std::vector<AdmissibleSet> sets = admissibleSets(part, f, tris);
    std::vector<std::pair<FinishingKind, Offer>> unseen;  // square or along the axis, not seen whole: tried later
    for (const AdmissibleSet& set : sets) {
      std::vector<Offer> offers;
      for (const Offer& o : setup_offers)
        if (admits(set, o.d, tolerance)) offers.push_back(o);
      if (set.freedom == Freedom::Zero)
        for (const Offer& o : ownDirectionOffers(setups, directions, set.axis, options)) offers.push_back(o);
      if (set.kind == FinishingKind::FaceMill || set.kind == FinishingKind::Contour) {
        for (const Offer& o : offers) {
          const double depth = set.kind == FinishingKind::Contour ? extentAlong(part.mesh, tris, o.d) : 0;
          if (sees(o)) add(set.kind, o, depth, true, "");
          else unseen.push_back({set.kind, o});
        }
      } else if (set.kind == FinishingKind::SideMill) {
        // The least depth first (4.3.1), and only depths some flat end mill's flutes reach.
        std::vector<std::pair<double, Offer>> by_depth;
        for (const Offer& o : offers)
          if (sees(o)) by_depth.push_back({extentAlong(part.mesh, tris, o.d), o});
        std::sort(by_depth.begin(), by_depth.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (const auto& [depth, o] : by_depth) {
          if (depth <= longest_flutes) add(set.kind, o, depth, true, "");
          else if (surface_note.empty())
            surface_note = "parallel to a setup direction but " + mm(depth) + " deep, beyond every flat end mill's " +
                           mm(longest_flutes) + " of flutes";
        }
      } else {  // 2-DOF surface finishing: the setups meeting the face most squarely, whole ones first
        for (const auto& [kind, o] : unseen)
          add(kind, o, kind == FinishingKind::Contour ? extentAlong(part.mesh, tris, o.d) : 0, false,
              "its direction sees only part of it");
        std::vector<std::pair<double, Offer>> scored;
        for (const Offer& o : setup_offers) {
          if (!admits(set, o.d, tolerance)) continue;
          int seen = 0;
          for (int t : tris) seen += visibility.map.bits.get(t, o.index) ? 1 : 0;
          if (seen == 0) continue;
          scored.push_back({(sees(o) ? 10.0 : 0.0) + leastDot(set, o.d) + static_cast<double>(seen) / tris.size(), o});
        }
        std::sort(scored.begin(), scored.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
        if (surface_note.empty() && (part.faces[f].type == SurfaceType::Plane || part.faces[f].type == SurfaceType::Cylinder))
          surface_note = part.faces[f].type == SurfaceType::Plane
                             ? "square to no setup direction and parallel to none within reach: surface finishing"
                             : "its axis is no setup direction: surface finishing";
        const bool five = options.mode == MachineMode::FiveAxis;
        const FinishingKind kind = five ? FinishingKind::Surface5Axis : FinishingKind::Surface3Axis;
        for (std::size_t i = 0; i < scored.size() && i < kSurfaceChoices; ++i) {
          Offer o = scored[i].second;
          // 5-axis: the face's own direction within the setup's tilt, the centre of its permissible cone (the
          // direction that meets its every normal most squarely, thesis 4.1.3's thinning): the ball's centres come
          // from a drop along it, the axis leans from the setup's towards it as the holder needs.
          if (five) {
            const double tilt = setups.max_tilt_deg * kPi / 180;
            double best = leastDot(set, o.d);
            for (int d = 0; d < directions.size(); ++d) {
              const Vec3& v = directions.directions[d];
              if (!coneHas(accessible, d) || std::acos(std::clamp(v.dot(setups.setups[o.setup].frame.z), -1.0, 1.0)) > tilt)
                continue;
              const double score = leastDot(set, v);
              if (score > best + 1e-9) best = score, o.index = d, o.d = v;
            }
          }
          add(kind, o, 0, scored[i].first >= 10.0, surface_note);
        }
      }
    }
    if (a.choices.empty()) a.reason = "no permissible direction: no setup direction both admits the face and sees it";
  }
  return out;
}

}  // namespace art2part
