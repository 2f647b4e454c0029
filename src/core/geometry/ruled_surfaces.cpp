// Pass 2 of face segmentation: cylinders and cones over planar patches. A tessellation cuts a cylinder or a cone
// into planar strips between rulings, so both are grown over patches from seeds of three neighbouring strips, and
// every patch that joins is checked against the fitted surface.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "segmentation_internal.h"

namespace art2part {
namespace segmentation {

namespace {

// Seeds.
constexpr double kSeedSpanRatio = 2.5;     // widest / narrowest strip of a seed (a tessellation makes them alike)
constexpr double kZigzagElongation = 3.0;  // length along the axis / width of a zigzag triangle that seeds
constexpr double kRoughFit = 10.0;         // of the tolerance: a seed whose first circle fit is off by more is none
constexpr double kRoughConeGuess = 100.0;  // of the tolerance: the same for a cone guessed from a seed
constexpr double kExactFit = 0.01;         // of the fine tolerance: a seed fitting this closely needs no other fit
constexpr double kConeFitsBetter = 4.0;    // a seed is a cone when the cone's residual is this much smaller
constexpr double kMaxConeHalfAngle = 80.0 * kPi / 180.0;  // flatter cones cannot be told from planes
// Regions.
constexpr double kSeedResidualMargin = 3.0;  // region tolerance / largest residual of its seed
constexpr int kMinDistinctVertices = 8;      // a fit of 5 or 6 parameters must be overdetermined
constexpr std::size_t kMaxFitPoints = 256;   // points a refit uses
const double kAlongRuling = std::sqrt(0.5);  // an edge at less than 45 degrees to the ruling runs along it

Vec3 edgeVector(const Mesh& mesh, const std::pair<int, int>& e) {
  return mesh.vertices[e.second] - mesh.vertices[e.first];
}

}  // namespace

double RuledSurface::distance(const Vec3& p) const {
  return is_cone ? distanceToCone(cone, p) : distanceToCylinder(cylinder, p);
}

Vec3 RuledSurface::radial(const Vec3& p) const {
  const Vec3 d = p - (is_cone ? cone.apex : cylinder.point);
  const Vec3 r = d - axis() * axis().dot(d);
  return r.norm() > 0.0 ? Vec3(r.normalized()) : Vec3::Zero();
}

Vec3 RuledSurface::normal(const Vec3& p) const {
  if (!is_cone) return radial(p);
  return radial(p) * std::cos(cone.half_angle) - cone.axis * std::sin(cone.half_angle);
}

Vec3 RuledSurface::ruling(const Vec3& p) const {
  if (!is_cone) return cylinder.axis;
  return cone.axis * std::cos(cone.half_angle) + radial(p) * std::sin(cone.half_angle);
}

namespace {

class RuledSurfaceFinder {
 public:
  RuledSurfaceFinder(const Mesh& mesh, const std::vector<PlanarPatch>& patches, const PatchGraph& graph,
                     const Tolerances& tol)
      : mesh_(mesh), patches_(patches), graph_(graph), tol_(tol), region_of_(patches.size(), -1),
        rejected_in_(patches.size(), -1), tried_(patches.size(), 0) {}

  std::vector<RuledRegion> find(std::vector<int>& region_of) {
    for (RuledRegion& fan : findConeFans(mesh_, patches_, tol_))
      if (growFan(fan)) regions_.push_back(std::move(fan));
    for (int q = 0; q < static_cast<int>(patches_.size()); ++q) {
      if (region_of_[q] >= 0 || tried_[q] || patches_[q].degenerate()) continue;
      RuledRegion region;
      if (seedAround(q, region)) regions_.push_back(std::move(region));
    }
    mergeSameSurfaces();
    region_of = region_of_;
    return regions_;
  }

 private:
  // Links from q to free patches across a gentle bend: the candidates for neighbouring strips, largest first (a
  // strip of the surface rather than a facet of the blend it runs into).
  std::vector<int> gentleLinks(int q) const {
    std::vector<int> out;
    for (int li : graph_.links_of[q]) {
      const PatchLink& link = graph_.links[li];
      const int p = link.other(q);
      if (region_of_[p] < 0 && !patches_[p].degenerate() && link.max_bend > tol_.angle &&
          link.max_bend <= tol_.max_bend)
        out.push_back(li);
    }
    std::stable_sort(out.begin(), out.end(), [&](int a, int b) {
      return patches_[graph_.links[a].other(q)].area > patches_[graph_.links[b].other(q)].area;
    });
    return out;
  }

  // A fan of strips round a cone's apex, fitted already (its patches checked against the cone): grow it.
  bool growFan(RuledRegion& region) {
    for (int p : region.patches)
      if (region_of_[p] >= 0) return false;
    setTolerance(region);
    double widest = 0.0;
    for (int p : region.patches) widest = std::max(widest, span(region.surface, p));
    region.span_limit = 2.0 * widest + tol_.angle;
    return grow(region);
  }

  // Patch q with neighbours on two sides: try the three as a cylinder, then as a cone, and grow what fits.
  bool seedAround(int q, RuledRegion& region) {
    const std::vector<int> links = gentleLinks(q);
    for (std::size_t i = 0; i < links.size(); ++i)
      for (std::size_t j = i + 1; j < links.size(); ++j) {
        const PatchLink& first = graph_.links[links[i]];
        const PatchLink& second = graph_.links[links[j]];
        region = RuledRegion();
        region.patches = {first.other(q), q, second.other(q)};
        if (bestSeed(region, first, second) && grow(region)) return true;
      }
    return false;
  }

  // The seed as a cylinder or as a cone, whichever fits: strips of a cone fit a cylinder too, only less closely
  // (and a cylinder fits no cone but one with a far apex and a tiny angle, which coneSeed refuses).
  bool bestSeed(RuledRegion& region, const PatchLink& first, const PatchLink& second) const {
    RuledRegion as_cone = region;
    const bool cylinder = cylinderSeed(region, first, second);
    if (cylinder && worstResidual(region) <= kExactFit * tol_.fine_distance) return true;  // no cone fits better
    if (!coneSeed(as_cone, first, second)) return cylinder;
    if (cylinder && worstResidual(region) <= kConeFitsBetter * worstResidual(as_cone)) return true;
    region = as_cone;
    return true;
  }

  double worstResidual(const RuledRegion& region) const {
    double worst = 0.0;
    for (const Vec3& p : pointsOf(region)) worst = std::max(worst, region.surface.distance(p));
    return worst;
  }

  // Three strips of a cylinder: their normals square to one axis (the direction least aligned with them all), and
  // the edges between them running along it.
  bool cylinderSeed(RuledRegion& region, const PatchLink& first, const PatchLink& second) const {
    std::vector<Vec3> normals;
    std::vector<double> weights;
    for (int p : region.patches) {
      normals.push_back(patches_[p].normal);
      weights.push_back(patches_[p].area);
    }
    const Vec3 axis = leastAlignedDirection(normals, weights);
    for (int p : region.patches)
      if (std::abs(patches_[p].normal.dot(axis)) > std::sin(std::min(kPi / 2, tol_.angle + patches_[p].normal_slack)))
        return false;
    if (!alongDirection(first, axis, kAlongRuling) || !alongDirection(second, axis, kAlongRuling)) return false;
    region.surface.is_cone = false;
    // The axis from the normals is close for strips and zigzags alike: a circle fit around it that misses by far
    // spares the full fit.
    const std::vector<Vec3> points = pointsOf(region);
    if (!fitCylinderAroundAxis(points, axis, region.surface.cylinder)) return false;
    const double rough = worstResidual(region);
    if (rough > kRoughFit * tol_.distance) return false;
    // Strips give the axis exactly; only zigzags need the full fit.
    if (rough > kExactFit * tol_.fine_distance && !fitCylinder(samplePointsOf(region), axis, region.surface.cylinder))
      return false;
    if (region.surface.cylinder.radius > tol_.max_radius) return false;
    // Strips meet along rulings. Where the two boundaries of a face were meshed apart, triangles zigzag between
    // them instead, long and thin along the axis. A seed of neither kind is three facets of a smooth free-form
    // surface, which any cylinder fits over so small a piece.
    const double strict = std::cos(tol_.angle);
    const bool strips = alongDirection(first, axis, strict) && alongDirection(second, axis, strict);
    if (!strips)
      for (int p : region.patches)
        if (extentAlong(p, region.surface.cylinder.axis) <
            kZigzagElongation * region.surface.cylinder.radius * span(region.surface, p))
          return false;
    return acceptSeed(region);
  }

  double extentAlong(int p, const Vec3& direction) const {
    double low = 0.0, high = 0.0;
    bool first = true;
    for (int v : patches_[p].vertices) {
      const double along = direction.dot(mesh_.vertices[v]);
      low = first ? along : std::min(low, along);
      high = first ? along : std::max(high, along);
      first = false;
    }
    return high - low;
  }

  // Three strips of a cone: the edges between them are rulings that meet at the apex, and the normals make one
  // angle with the axis, so their tips lie on a plane square to it.
  bool coneSeed(RuledRegion& region, const PatchLink& first, const PatchLink& second) const {
    for (int p : region.patches)
      if (patches_[p].vertices.size() < 4) return false;  // a strip has two rulings; single triangles fit anything
    std::vector<Vec3> points, directions;
    for (const PatchLink* link : {&first, &second})
      for (const auto& e : link->edges) {
        const Vec3 d = edgeVector(mesh_, e);
        if (d.norm() <= 0.0) continue;
        points.push_back(mesh_.vertices[e.first]);
        directions.push_back(d.normalized());
      }
    ConeSurface guess;
    if (!nearestPointToLines(points, directions, guess.apex)) return false;
    // Rulings meet at the apex; edges of any other surface pass it by (this spares most fits).
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Vec3 d = guess.apex - points[k];
      if ((d - directions[k] * directions[k].dot(d)).norm() > tol_.distance) return false;
    }
    const Vec3 n0 = patches_[region.patches[0]].normal, n1 = patches_[region.patches[1]].normal,
               n2 = patches_[region.patches[2]].normal;
    const Vec3 axis = (n1 - n0).cross(n2 - n0);
    if (axis.norm() <= 0.0) return false;
    Vec3 middle = Vec3::Zero();
    for (int p : region.patches) middle += patches_[p].centroid() / 3.0;
    guess.axis = axis.normalized() * (axis.dot(middle - guess.apex) < 0.0 ? -1.0 : 1.0);
    guess.half_angle = std::acos(std::min(1.0, guess.axis.dot((middle - guess.apex).normalized())));
    region.surface.is_cone = true;
    region.surface.cone = guess;
    // Close for three strips of a cone (the axis from three close normals is rough); far off for anything else,
    // which spares the full fit.
    if (!(guess.half_angle > 0.0) || worstResidual(region) > kRoughConeGuess * tol_.distance) return false;
    if (!fitCone(samplePointsOf(region), guess, region.surface.cone)) return false;
    const ConeSurface& cone = region.surface.cone;
    // Nearly a cylinder, or an apex far outside the part: not a cone we can use.
    if (cone.half_angle < tol_.angle || cone.half_angle > kMaxConeHalfAngle ||
        (cone.apex - middle).norm() > tol_.max_radius)
      return false;
    for (const PatchLink* link : {&first, &second})
      for (const auto& e : link->edges)
        if (std::abs(edgeVector(mesh_, e).normalized().dot(region.surface.ruling(mesh_.vertices[e.first]))) <
            kAlongRuling)
          return false;
    return acceptSeed(region);
  }

  // Every edge of the link within the angle whose cosine is given of the direction (less noise for short edges).
  bool alongDirection(const PatchLink& link, const Vec3& direction, double min_cosine) const {
    for (const auto& e : link.edges) {
      const Vec3 d = edgeVector(mesh_, e);
      if (std::abs(d.dot(direction)) < min_cosine * d.norm() - 2.0 * tol_.noise) return false;
    }
    return true;
  }

  // The seed's strips must lie on the fitted surface and be alike in width, as a tessellation makes them: three
  // patches of any widths fit some circle when they are symmetric (strip, flat, strip across a flat between two
  // fillets), and a strip seen end-on between two tiny facets fits a huge one.
  bool acceptSeed(RuledRegion& region) const {
    setConcavity(region);
    setTolerance(region);
    double widest = 0.0, narrowest = kPi;
    for (int p : region.patches) {
      widest = std::max(widest, span(region.surface, p));
      narrowest = std::min(narrowest, span(region.surface, p));
    }
    if (widest > kSeedSpanRatio * narrowest + tol_.angle) return false;
    region.span_limit = 2.0 * widest + tol_.angle;
    for (int p : region.patches)
      if (!belongs(region, p)) return false;
    return true;
  }

  // How far the region's vertices may lie from its surface: what its seed shows, with a margin, between the fine
  // and the coarse tolerance. A CAD tessellation is exact but where a B-rep edge is a spline approximation; a
  // tolerance no wider than needed keeps out the facets of a torus or sphere a fillet runs into, and the bands of a
  // torus, which are near cylinders.
  void setTolerance(RuledRegion& region) const {
    region.tolerance =
        std::min(tol_.distance, std::max(tol_.fine_distance, kSeedResidualMargin * worstResidual(region)));
  }

  std::vector<Vec3> pointsOf(const RuledRegion& region) const {
    std::vector<Vec3> points;
    for (int p : region.patches)
      for (int v : patches_[p].vertices) points.push_back(mesh_.vertices[v]);
    return points;
  }

  // An even sample of the region's points: a fit of five or six parameters needs no more, and refits of a long
  // fillet stay cheap.
  std::vector<Vec3> samplePointsOf(const RuledRegion& region) const {
    std::vector<Vec3> points = pointsOf(region);
    if (points.size() <= kMaxFitPoints) return points;
    std::vector<Vec3> sample;
    sample.reserve(kMaxFitPoints);
    for (std::size_t i = 0; i < kMaxFitPoints; ++i) sample.push_back(points[i * points.size() / kMaxFitPoints]);
    return sample;
  }

  // Concave (a hole) when the outward normals point towards the axis.
  void setConcavity(RuledRegion& region) const {
    double outwardness = 0.0;
    for (int p : region.patches)
      outwardness += patches_[p].area_vector.dot(region.surface.radial(patches_[p].centroid()));
    region.concave = outwardness < 0.0;
  }

  bool refit(RuledRegion& region) const {
    RuledSurface surface = region.surface;
    const std::vector<Vec3> points = samplePointsOf(region);
    const bool fitted = surface.is_cone ? fitCone(points, region.surface.cone, surface.cone)
                                        : fitCylinder(points, region.surface.cylinder.axis, surface.cylinder);
    if (!fitted || (!surface.is_cone && surface.cylinder.radius > tol_.max_radius) ||
        (surface.is_cone && surface.cone.half_angle > kMaxConeHalfAngle))
      return false;
    region.surface = surface;
    setConcavity(region);
    return true;
  }

  // Angle the patch's vertices cover around the axis.
  double span(const RuledSurface& surface, int p) const {
    const Vec3 reference = surface.radial(patches_[p].centroid());
    const Vec3 side = surface.axis().cross(reference);
    double low = 0.0, high = 0.0;
    for (int v : patches_[p].vertices) {
      const Vec3 r = surface.radial(mesh_.vertices[v]);
      const double angle = std::atan2(r.dot(side), r.dot(reference));
      low = std::min(low, angle);
      high = std::max(high, angle);
    }
    return high - low;
  }

  // How far the patch's normal may lean along the ruling. A strip (corners on two rulings) leans only by rounding
  // and by corners off the surface by the region's tolerance, more for a short strip; a triangle with corners on
  // three rulings (two boundaries meshed apart) leans by the sagitta of its span over its length.
  double rulingSlack(const RuledRegion& region, int p) const {
    const Vec3 centroid = patches_[p].centroid();
    const double length = extentAlong(p, region.surface.ruling(centroid));
    const double sagitta = localRadius(region.surface, centroid) * (1.0 - std::cos(0.5 * span(region.surface, p)));
    return std::max(patches_[p].normal_slack, length > 0.0 ? std::atan((region.tolerance + sagitta) / length) : kPi);
  }

  static double localRadius(const RuledSurface& surface, const Vec3& p) {
    if (!surface.is_cone) return surface.cylinder.radius;
    const Vec3 d = p - surface.cone.apex;
    return (d - surface.cone.axis * surface.cone.axis.dot(d)).norm();
  }

  // A patch belongs to the surface when its vertices lie on it and it faces the way the surface does there: square
  // to the ruling, as every facet of a tessellated cylinder or cone is (its corners sit on two rulings), and
  // outwards on the surface's side. The ruling test is what keeps out the facets of a torus a fillet runs into,
  // which lie within the distance tolerance near the joint but lean along the axis. Last, a patch of more than one
  // triangle is no wider than the strips it grew from (a flat cut along a shaft has all its corners on the
  // cylinder); single triangles may be wider (a cone's fan round its apex).
  bool belongs(const RuledRegion& region, int p) const {
    const PlanarPatch& patch = patches_[p];
    const RuledSurface& surface = region.surface;
    const Vec3 centroid = patch.centroid();
    const Vec3 outward = (region.concave ? -1.0 : 1.0) * surface.normal(centroid);
    if (patch.normal.dot(outward) < std::cos(tol_.max_bend)) return false;
    if (std::abs(patch.normal.dot(surface.ruling(centroid))) >
        std::sin(std::min(kPi / 2, tol_.angle + rulingSlack(region, p))))
      return false;
    for (int v : patch.vertices)
      if (surface.distance(mesh_.vertices[v]) > region.tolerance) return false;
    return patch.vertices.size() <= 3 || span(surface, p) <= region.span_limit;
  }

  // Neighbouring regions on one surface are one face whose growth was blocked somewhere (a sliver, a facet too
  // wide): join them, refit, and renumber.
  void mergeSameSurfaces() {
    std::vector<int> parent(regions_.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
    auto root = [&](int i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (const PatchLink& link : graph_.links) {
      const int a = region_of_[link.a], b = region_of_[link.b];
      if (a < 0 || b < 0 || root(a) == root(b) || link.max_bend > tol_.max_bend) continue;
      if (sameSurface(regions_[root(a)], regions_[root(b)])) parent[root(b)] = root(a);
    }
    std::vector<RuledRegion> merged;
    std::vector<int> new_id(regions_.size(), -1);
    for (std::size_t i = 0; i < regions_.size(); ++i) {
      const int r = root(static_cast<int>(i));
      if (new_id[r] < 0) {
        new_id[r] = static_cast<int>(merged.size());
        merged.push_back(regions_[r]);
        merged.back().patches.clear();
      }
    }
    for (std::size_t i = 0; i < regions_.size(); ++i) {
      RuledRegion& target = merged[new_id[root(static_cast<int>(i))]];
      target.patches.insert(target.patches.end(), regions_[i].patches.begin(), regions_[i].patches.end());
    }
    for (int& r : region_of_)
      if (r >= 0) r = new_id[root(r)];
    std::vector<char> joined(merged.size(), 0);
    for (std::size_t i = 0; i < regions_.size(); ++i)
      if (root(static_cast<int>(i)) != static_cast<int>(i)) joined[new_id[root(static_cast<int>(i))]] = 1;
    for (std::size_t i = 0; i < merged.size(); ++i)
      if (joined[i]) refit(merged[i]);
    regions_.swap(merged);
  }

  bool sameSurface(const RuledRegion& a, const RuledRegion& b) const {
    if (a.surface.is_cone != b.surface.is_cone || a.concave != b.concave) return false;
    const double length = std::max(a.tolerance, b.tolerance);
    if (a.surface.is_cone) {
      const ConeSurface &p = a.surface.cone, &q = b.surface.cone;
      return angleOf(p.axis, q.axis) <= tol_.angle && std::abs(p.half_angle - q.half_angle) <= tol_.angle &&
             (p.apex - q.apex).norm() <= tol_.distance;
    }
    const CylinderSurface &p = a.surface.cylinder, &q = b.surface.cylinder;
    const Vec3 d = q.point - p.point;
    return std::abs(p.axis.dot(q.axis)) >= std::cos(tol_.angle) && std::abs(p.radius - q.radius) <= length &&
           (d - p.axis * p.axis.dot(d)).norm() <= length;
  }

  static double angleOf(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

  int distinctVertices(const RuledRegion& region) const {
    std::vector<int> vertices;
    for (int p : region.patches)
      vertices.insert(vertices.end(), patches_[p].vertices.begin(), patches_[p].vertices.end());
    std::sort(vertices.begin(), vertices.end());
    return static_cast<int>(std::unique(vertices.begin(), vertices.end()) - vertices.begin());
  }

  // Breadth-first over gentle bends, refitting as the region grows (every quarter more points), so the surface
  // stays true over a long arc. Returns false (and frees the patches) when the result is not a usable surface.
  bool grow(RuledRegion& region) {
    const int id = static_cast<int>(regions_.size());
    const int attempt = attempts_++;
    for (int p : region.patches) region_of_[p] = id;
    std::size_t fitted_points = pointsOf(region).size(), points = fitted_points;
    for (std::size_t head = 0; head < region.patches.size(); ++head) {
      for (int li : graph_.links_of[region.patches[head]]) {
        const PatchLink& link = graph_.links[li];
        const int s = link.other(region.patches[head]);
        if (region_of_[s] >= 0 || rejected_in_[s] == attempt || link.max_bend > tol_.max_bend) continue;
        if (patches_[s].degenerate() || !belongs(region, s)) {
          rejected_in_[s] = attempt;
          continue;
        }
        region_of_[s] = id;
        region.patches.push_back(s);
        points += patches_[s].vertices.size();
        if (points * 4 > fitted_points * 5) {
          RuledRegion refitted = region;
          if (refit(refitted)) region = refitted;
          fitted_points = points;
        }
      }
    }
    RuledRegion final_fit = region;
    if (refit(final_fit)) region = final_fit;
    const RegionContext context{mesh_, patches_, graph_, tol_, region_of_};
    if (static_cast<int>(region.patches.size()) >= tol_.min_strips &&
        distinctVertices(region) >= kMinDistinctVertices && !bandOfRevolution(context, region, id))
      return true;
    for (int p : region.patches) {
      region_of_[p] = -1;
      tried_[p] = 1;  // seeding from it again would mostly grow the same region
    }
    return false;
  }

  const Mesh& mesh_;
  const std::vector<PlanarPatch>& patches_;
  const PatchGraph& graph_;
  const Tolerances& tol_;
  std::vector<int> region_of_;
  std::vector<int> rejected_in_;   // the growth attempt that last rejected each patch
  std::vector<char> tried_;        // patches of a region that was grown and dropped: no longer seeds
  std::vector<RuledRegion> regions_;
  int attempts_ = 0;
};

}  // namespace

std::vector<RuledRegion> findRuledSurfaces(const Mesh& mesh, const std::vector<PlanarPatch>& patches,
                                           const PatchGraph& graph, const Tolerances& tol,
                                           std::vector<int>& ruled_of) {
  RuledSurfaceFinder finder(mesh, patches, graph, tol);
  return finder.find(ruled_of);
}

}  // namespace segmentation
}  // namespace art2part
