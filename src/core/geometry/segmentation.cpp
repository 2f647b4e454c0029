// Face segmentation of a triangle mesh in three passes:
//  1. planar patches: region growing over manifold edges, each triangle joining the patch whose plane holds its
//     corners and whose normal it shares;
//  2. cylinders: a tessellated cylinder is a ring of thin planar strips bent along edges parallel to its axis, so
//     cylinders are grown over patches from seeds of three such strips, every patch checked against the fitted
//     surface;
//  3. what is left: a planar patch is a plane unless it is one of a chain of small facets bending smoothly into each
//     other (a cone, a fillet with too few strips, free-form); the facets of such chains are grouped into free-form
//     ("other") segments, split at sharp edges.
#include "art2part/geometry/segmentation.h"

#include <Eigen/Geometry>  // cross products (mesh.h brings only Eigen/Core)
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <cstdio>
#include <cstdlib>

#include "art2part/geometry/surface_fit.h"

namespace art2part {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSeedSpanRatio = 1.5;  // widest / narrowest strip of a cylinder seed

// The options resolved for one mesh.
struct Tolerances {
  double distance = 0.0;  // mm: how far a vertex may lie from its fitted surface
  double noise = 0.0;     // mm: rounding of vertex positions, which turns the normals of small triangles
  double angle = 0.0;     // rad: normal deviation within a plane
  double max_bend = 0.0;  // rad: largest bend between two strips of one tessellated curved surface
  double max_radius = 0.0;  // mm: a larger "cylinder" is a gently bent sheet, not a feature
  int min_cylinder_strips = 3;
  int min_plane_triangles = 3;
};

Tolerances resolveTolerances(const Mesh& mesh, const SegmentationOptions& options) {
  const double diagonal = boundingBox(mesh).diagonal();
  Tolerances tol;
  // CAD tessellations put vertices on their surface up to the B-rep's own edge tolerance: intersection curves
  // approximated by splines leave boundary vertices up to 3e-5 of the part off a cylinder in NIST CTC 2, so 1e-4.
  // Surfaces that this cannot tell apart (a plane tangent to a fillet) differ in their normals.
  tol.distance = options.distance_tolerance >= 0.0 ? options.distance_tolerance : 1e-4 * diagonal;
  // Rounding of positions: float32 in an STL file (6e-8 of the coordinates) and vertex merging (1e-6 of the part).
  tol.noise = 1e-6 * diagonal;
  tol.angle = options.angle_tolerance;
  tol.max_bend = options.max_strip_bend;
  tol.max_radius = 10.0 * diagonal;
  tol.min_cylinder_strips = std::max(3, options.min_cylinder_strips);
  tol.min_plane_triangles = std::max(1, options.min_plane_triangles);
  return tol;
}

// What one triangle contributes to a fit.
struct Facet {
  Vec3 normal = Vec3::Zero();
  Vec3 centroid = Vec3::Zero();
  double area = 0.0;
  double normal_slack = kPi;  // rad: how far rounding of its corners may turn the normal (all the way if degenerate)
};

std::vector<Facet> describeFacets(const Mesh& mesh, const Tolerances& tol) {
  std::vector<Facet> facets(mesh.triangles.size());
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    Facet& f = facets[t];
    f.normal = triangleNormal(mesh, t);
    f.centroid = triangleCentroid(mesh, t);
    f.area = triangleArea(mesh, t);
    double longest = 0.0;
    for (int i = 0; i < 3; ++i) longest = std::max(longest, (mesh.corner(t, (i + 1) % 3) - mesh.corner(t, i)).norm());
    const double min_height = longest > 0.0 ? 2.0 * f.area / longest : 0.0;
    if (f.area > 0.0 && min_height > 0.0 && f.normal.norm() > 0.0)
      f.normal_slack = std::min(kPi, 2.0 * tol.noise / min_height);
  }
  return facets;
}

double angleBetween(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// ---------------------------------------------------------------------------------------------------------------
// Pass 1: planar patches.

struct PlanarPatch {
  std::vector<int> triangles;
  std::vector<int> vertices;  // distinct, filled after growing
  Vec3 area_vector = Vec3::Zero();  // sum of area x normal: its direction is the area-weighted normal
  Vec3 moment = Vec3::Zero();       // sum of area x centroid
  double area = 0.0;
  double normal_slack = kPi;  // of its most reliable triangle
  Vec3 normal = Vec3::Zero();
  double offset = 0.0;

  Vec3 centroid() const { return area > 0.0 ? Vec3(moment / area) : Vec3::Zero(); }
  bool degenerate() const { return normal.norm() == 0.0; }

  void add(int t, const Facet& f) {
    triangles.push_back(t);
    area_vector += f.area * f.normal;
    moment += f.area * f.centroid;
    area += f.area;
    normal_slack = std::min(normal_slack, f.normal_slack);
    const double length = area_vector.norm();
    if (length > 0.0) {
      normal = area_vector / length;
      offset = normal.dot(centroid());
    }
  }
};

bool fitsPlane(const Mesh& mesh, const Facet& f, int t, const PlanarPatch& patch, const Tolerances& tol) {
  for (int i = 0; i < 3; ++i)
    if (std::abs(patch.normal.dot(mesh.corner(t, i)) - patch.offset) > tol.distance) return false;
  return angleBetween(f.normal, patch.normal) <= tol.angle + f.normal_slack;
}

// Grows a patch from the seed over manifold edges; patch_of marks its triangles.
PlanarPatch growPlane(const Mesh& mesh, const Adjacency& adjacency, const std::vector<Facet>& facets,
                      const Tolerances& tol, int seed, int id, std::vector<int>& patch_of) {
  PlanarPatch patch;
  patch.add(seed, facets[seed]);
  patch_of[seed] = id;
  if (patch.degenerate()) return patch;  // no plane to grow: a lone degenerate triangle
  std::vector<int> stack{seed};
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    for (int u : adjacency.neighbour[t]) {
      if (u < 0 || patch_of[u] >= 0 || !fitsPlane(mesh, facets[u], u, patch, tol)) continue;
      patch_of[u] = id;
      patch.add(u, facets[u]);
      stack.push_back(u);
    }
  }
  return patch;
}

std::vector<PlanarPatch> findPlanarPatches(const Mesh& mesh, const Adjacency& adjacency,
                                           const std::vector<Facet>& facets, const Tolerances& tol,
                                           std::vector<int>& patch_of) {
  // Largest triangles first: they carry the most reliable normals and the largest faces.
  std::vector<int> order(mesh.triangles.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return facets[a].area > facets[b].area; });
  patch_of.assign(mesh.triangles.size(), -1);
  std::vector<PlanarPatch> patches;
  for (int seed : order)
    if (patch_of[seed] < 0)
      patches.push_back(growPlane(mesh, adjacency, facets, tol, seed, static_cast<int>(patches.size()), patch_of));
  for (PlanarPatch& patch : patches) {
    for (int t : patch.triangles) patch.vertices.insert(patch.vertices.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
    std::sort(patch.vertices.begin(), patch.vertices.end());
    patch.vertices.erase(std::unique(patch.vertices.begin(), patch.vertices.end()), patch.vertices.end());
  }
  return patches;
}

// Which patches touch across manifold edges, along which edges, and how sharply they bend there.
struct PatchLink {
  int a = -1, b = -1;
  std::vector<std::pair<int, int>> edges;  // vertex ids
  double max_bend = 0.0;                  // rad, largest |dihedral| along the shared edges
  int other(int p) const { return p == a ? b : a; }
};

struct PatchGraph {
  std::vector<PatchLink> links;
  std::vector<std::vector<int>> links_of;  // per patch
};

PatchGraph linkPatches(const Mesh& mesh, const Adjacency& adjacency, const std::vector<int>& patch_of,
                       int patch_count) {
  PatchGraph graph;
  graph.links_of.resize(patch_count);
  std::unordered_map<std::uint64_t, int> index;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int e = 0; e < 3; ++e) {
      const int u = adjacency.neighbour[t][e];
      if (u < t || patch_of[u] == patch_of[t]) continue;  // each manifold edge once, patch borders only
      const int a = std::min(patch_of[t], patch_of[u]), b = std::max(patch_of[t], patch_of[u]);
      const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
      auto found = index.emplace(key, static_cast<int>(graph.links.size()));
      if (found.second) {
        graph.links.push_back(PatchLink{a, b, {}, 0.0});
        graph.links_of[a].push_back(found.first->second);
        graph.links_of[b].push_back(found.first->second);
      }
      PatchLink& link = graph.links[found.first->second];
      link.edges.emplace_back(mesh.triangles[t][e], mesh.triangles[t][(e + 1) % 3]);
      link.max_bend = std::max(link.max_bend, std::abs(adjacency.dihedral[t][e]));
    }
  return graph;
}

// ---------------------------------------------------------------------------------------------------------------
// Pass 2: cylinders over patches.

struct CylinderRegion {
  std::vector<int> patches;
  CylinderSurface surface;
  bool concave = false;
  double span_limit = 0.0;  // rad: widest patch it takes, from its seed strips
};

class CylinderFinder {
 public:
  CylinderFinder(const Mesh& mesh, const std::vector<PlanarPatch>& patches, const PatchGraph& graph,
                 const Tolerances& tol)
      : mesh_(mesh), patches_(patches), graph_(graph), tol_(tol), cylinder_of_(patches.size(), -1),
        rejected_in_(patches.size(), -1), failed_seed_(patches.size(), 0) {}

  // Finds the cylinders; cylinderOf() then tells each patch's.
  std::vector<CylinderRegion> find() {
    for (int q = 0; q < static_cast<int>(patches_.size()); ++q) {
      if (cylinder_of_[q] >= 0 || failed_seed_[q]) continue;
      CylinderRegion region;
      if (seedAround(q, region)) regions_.push_back(std::move(region));
    }
    return regions_;
  }
  const std::vector<int>& cylinderOf() const { return cylinder_of_; }

 private:
  // Links from q to free patches across a gentle bend: the candidates for neighbouring strips.
  std::vector<int> gentleLinks(int q) const {
    std::vector<int> out;
    for (int li : graph_.links_of[q]) {
      const PatchLink& link = graph_.links[li];
      const int p = link.other(q);
      if (cylinder_of_[p] < 0 && !patches_[p].degenerate() && link.max_bend > tol_.angle &&
          link.max_bend <= tol_.max_bend)
        out.push_back(li);
    }
    return out;
  }

  // A patch q with strips on two sides whose shared edges run parallel: try the three as a cylinder and grow it.
  bool seedAround(int q, CylinderRegion& region) {
    if (patches_[q].degenerate()) return false;
    const std::vector<int> links = gentleLinks(q);
    for (std::size_t i = 0; i < links.size(); ++i) {
      const Vec3 axis = longestEdgeDirection(graph_.links[links[i]]);
      if (!alongAxis(graph_.links[links[i]], axis)) continue;
      for (std::size_t j = i + 1; j < links.size(); ++j) {
        const int p = graph_.links[links[i]].other(q), r = graph_.links[links[j]].other(q);
        if (!alongAxis(graph_.links[links[j]], axis) || !acrossAxis(p, axis) || !acrossAxis(q, axis) ||
            !acrossAxis(r, axis))
          continue;
        region = CylinderRegion();
        region.patches = {p, q, r};
        if (fitSeed(region) && grow(region)) return true;
      }
    }
    return false;
  }

  Vec3 longestEdgeDirection(const PatchLink& link) const {
    Vec3 best = Vec3::Zero();
    for (const auto& e : link.edges) {
      const Vec3 d = mesh_.vertices[e.second] - mesh_.vertices[e.first];
      if (d.squaredNorm() > best.squaredNorm()) best = d;
    }
    return best.norm() > 0.0 ? Vec3(best.normalized()) : best;
  }

  // Every shared edge of the link parallel to the axis: the bends of a tessellated cylinder are its rulings.
  bool alongAxis(const PatchLink& link, const Vec3& axis) const {
    if (axis.norm() == 0.0) return false;
    for (const auto& e : link.edges) {
      const Vec3 d = mesh_.vertices[e.second] - mesh_.vertices[e.first];
      if (d.cross(axis).norm() > 2.0 * tol_.distance + d.norm() * std::sin(tol_.angle)) return false;
    }
    return true;
  }

  bool acrossAxis(int p, const Vec3& axis) const {
    return std::abs(patches_[p].normal.dot(axis)) <= std::sin(std::min(kPi / 2, tol_.angle + patches_[p].normal_slack));
  }

  std::vector<Vec3> pointsOf(const CylinderRegion& region) const {
    std::vector<Vec3> points;
    for (int p : region.patches)
      for (int v : patches_[p].vertices) points.push_back(mesh_.vertices[v]);
    return points;
  }

  // Fits the surface to the region's patches; the axis starts from the given guess.
  bool fit(CylinderRegion& region, const Vec3& axis_guess) const {
    CylinderSurface surface;
    if (!fitCylinder(pointsOf(region), axis_guess, surface) || surface.radius > tol_.max_radius) return false;
    region.surface = surface;
    // Concave (a hole) when the outward normals point towards the axis.
    double outwardness = 0.0;
    for (int p : region.patches) outwardness += patches_[p].area_vector.dot(radial(surface, patches_[p].centroid()));
    region.concave = outwardness < 0.0;
    return true;
  }

  static Vec3 radial(const CylinderSurface& c, const Vec3& x) {
    const Vec3 d = x - c.point;
    const Vec3 r = d - c.axis * c.axis.dot(d);
    return r.norm() > 0.0 ? Vec3(r.normalized()) : Vec3::Zero();
  }

  // Angle the patch's vertices cover around the axis.
  double span(const CylinderSurface& c, int p) const {
    const Vec3 reference = radial(c, patches_[p].centroid());
    const Vec3 side = c.axis.cross(reference);
    double low = 0.0, high = 0.0;
    for (int v : patches_[p].vertices) {
      const Vec3 r = radial(c, mesh_.vertices[v]);
      const double angle = std::atan2(r.dot(side), r.dot(reference));
      low = std::min(low, angle);
      high = std::max(high, angle);
    }
    return high - low;
  }

  // A patch belongs to the cylinder when its vertices lie on it and it faces the way the surface does there: square
  // to the axis, as every facet of a tessellated cylinder is (its corners sit on two rulings), and outwards on the
  // cylinder's side. The axis test is what keeps out the facets of a torus a fillet runs into, which lie within the
  // distance tolerance near the joint but lean along the axis. Last, the patch is no wider than the strips it grew
  // from (a flat cut along a shaft has all its corners on the cylinder).
  bool belongs(const CylinderRegion& region, int p) const {
    const PlanarPatch& patch = patches_[p];
    const Vec3& axis = region.surface.axis;
    const Vec3 outward = (region.concave ? -1.0 : 1.0) * radial(region.surface, patch.centroid());
    if (patch.normal.dot(outward) < std::cos(tol_.max_bend)) return false;
    if (std::abs(patch.normal.dot(axis)) > std::sin(std::min(kPi / 2, tol_.angle + axialSlack(region, p))))
      return false;
    for (int v : patch.vertices)
      if (distanceToCylinder(region.surface, mesh_.vertices[v]) > tol_.distance) return false;
    return span(region.surface, p) <= region.span_limit;
  }

  // How far the patch's normal may lean along the axis because its corners are off by the distance tolerance: a
  // short strip at a spline-approximated boundary leans more than a long one.
  double axialSlack(const CylinderRegion& region, int p) const {
    double low = 0.0, high = 0.0;
    bool first = true;
    for (int v : patches_[p].vertices) {
      const double along = region.surface.axis.dot(mesh_.vertices[v]);
      low = first ? along : std::min(low, along);
      high = first ? along : std::max(high, along);
      first = false;
    }
    const double length = high - low;
    return std::max(patches_[p].normal_slack, length > 0.0 ? std::atan(tol_.distance / length) : kPi);
  }

  // The seed's strips must lie on the fitted cylinder and be alike in width, as a tessellation makes them: three
  // patches of any widths fit some circle when they are symmetric (strip, flat, strip across a flat between two
  // fillets), and a strip seen end-on between two tiny facets fits a huge one.
  bool fitSeed(CylinderRegion& region) const {
    std::vector<Vec3> normals;
    std::vector<double> weights;
    for (int p : region.patches) {
      normals.push_back(patches_[p].normal);
      weights.push_back(patches_[p].area);
    }
    if (!fit(region, leastAlignedDirection(normals, weights))) return false;
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

  // A doubly curved surface of revolution (torus, sphere) tessellated in a grid falls apart into bands between two
  // meridians that each look like a short cylinder. Such a band ends where it bends gently into the next band, along
  // meridian edges that lean from the plane across its axis by half the band's angle. A real cylinder that ends in
  // a gentle bend (a fillet running into a corner blend) ends on a circle square to its axis.
  bool bandOfRevolution(const CylinderRegion& region) const {
    double leaning = 0.0, length = 0.0;
    for (int m : region.patches)
      for (int li : graph_.links_of[m]) {
        const PatchLink& link = graph_.links[li];
        const int s = link.other(m);
        if (cylinder_of_[s] == cylinder_of_[m] || link.max_bend > tol_.max_bend ||
            static_cast<int>(patches_[s].triangles.size()) >= tol_.min_plane_triangles)
          continue;
        for (const auto& e : link.edges) {
          const Vec3 d = mesh_.vertices[e.second] - mesh_.vertices[e.first];
          const double along = std::abs(d.dot(region.surface.axis));
          if (along > std::sqrt(0.5) * d.norm()) continue;  // a side of the cylinder, not an end
          leaning += along;
          length += d.norm();
        }
      }
    if (getenv("BANDDBG")) fprintf(stderr, "band? r=%.3f patches=%zu leaning=%.4f length=%.3f ratio=%.4f\n", region.surface.radius, region.patches.size(), leaning, length, length > 0 ? leaning/length : 0.0);
    return length > 0.0 && leaning > std::sin(tol_.angle) * length;
  }

  // Breadth-first over gentle bends, refitting as the region grows (every quarter more points), so the surface
  // stays true over a long arc. Returns false (and frees the patches) when it ends with too few strips.
  bool grow(CylinderRegion& region) {
    const int id = static_cast<int>(regions_.size());
    const int attempt = attempts_++;
    for (int p : region.patches) cylinder_of_[p] = id;
    std::size_t fitted_points = pointsOf(region).size(), points = fitted_points;
    for (std::size_t head = 0; head < region.patches.size(); ++head) {
      for (int li : graph_.links_of[region.patches[head]]) {
        const PatchLink& link = graph_.links[li];
        const int s = link.other(region.patches[head]);
        if (cylinder_of_[s] >= 0 || rejected_in_[s] == attempt || link.max_bend > tol_.max_bend) continue;
        if (patches_[s].degenerate() || !belongs(region, s)) {
          rejected_in_[s] = attempt;
          continue;
        }
        cylinder_of_[s] = id;
        region.patches.push_back(s);
        points += patches_[s].vertices.size();
        if (points * 4 > fitted_points * 5) {
          CylinderRegion refitted = region;
          if (fit(refitted, region.surface.axis)) region = refitted;
          fitted_points = points;
        }
      }
    }
    CylinderRegion final_fit = region;
    if (fit(final_fit, region.surface.axis)) region = final_fit;
    if (static_cast<int>(region.patches.size()) >= tol_.min_cylinder_strips && !bandOfRevolution(region)) return true;
    for (int p : region.patches) {
      cylinder_of_[p] = -1;
      failed_seed_[p] = 1;  // seeding from it again would only grow the same region
    }
    return false;
  }

  const Mesh& mesh_;
  const std::vector<PlanarPatch>& patches_;
  const PatchGraph& graph_;
  const Tolerances& tol_;
  std::vector<int> cylinder_of_;
  std::vector<int> rejected_in_;  // the growth attempt that last rejected each patch
  std::vector<char> failed_seed_;  // patches of a region that was grown and dropped
  std::vector<CylinderRegion> regions_;
  int attempts_ = 0;
};

// ---------------------------------------------------------------------------------------------------------------
// Pass 3: planes and free-form.

// A patch of a few triangles that bends gently into another such patch is a facet of a curved surface we do not fit
// (a cone, a fillet of two strips, free-form), not a plane. Big patches and cylinder strips are surfaces already.
std::vector<char> findRealPlanes(const std::vector<PlanarPatch>& patches, const PatchGraph& graph,
                                 const std::vector<int>& cylinder_of, const Tolerances& tol) {
  auto small = [&](int p) {
    return cylinder_of[p] < 0 && static_cast<int>(patches[p].triangles.size()) < tol.min_plane_triangles;
  };
  std::vector<char> plane(patches.size(), 0);
  for (std::size_t p = 0; p < patches.size(); ++p) {
    if (cylinder_of[p] >= 0 || patches[p].degenerate()) continue;
    bool facet_of_curve = false;
    if (small(static_cast<int>(p)))
      for (int li : graph.links_of[p]) {
        const PatchLink& link = graph.links[li];
        if (link.max_bend <= tol.max_bend && small(link.other(static_cast<int>(p)))) facet_of_curve = true;
      }
    plane[p] = !facet_of_curve;
  }
  return plane;
}

// Connected groups of free-form triangles, not crossing sharp edges (those separate faces of a free-form part too).
std::vector<int> groupFreeForm(const Adjacency& adjacency, const std::vector<char>& free_form, const Tolerances& tol,
                               int* count) {
  std::vector<int> group(free_form.size(), -1);
  int next = 0;
  std::vector<int> stack;
  for (std::size_t seed = 0; seed < free_form.size(); ++seed) {
    if (!free_form[seed] || group[seed] >= 0) continue;
    group[seed] = next;
    stack.push_back(static_cast<int>(seed));
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int e = 0; e < 3; ++e) {
        const int u = adjacency.neighbour[t][e];
        if (u < 0 || !free_form[u] || group[u] >= 0 || std::abs(adjacency.dihedral[t][e]) > tol.max_bend) continue;
        group[u] = next;
        stack.push_back(u);
      }
    }
    ++next;
  }
  *count = next;
  return group;
}

Face planeFace(const PlanarPatch& patch) {
  Face face;
  face.type = SurfaceType::Plane;
  face.normal = patch.normal;
  face.offset = patch.offset;
  return face;
}

Face cylinderFace(const CylinderRegion& region) {
  Face face;
  face.type = SurfaceType::Cylinder;
  Vec3 axis = region.surface.axis;
  // The sign of an axis means nothing: make it canonical (largest component positive) so results are stable.
  Eigen::Index largest = 0;
  axis.cwiseAbs().maxCoeff(&largest);
  if (axis(largest) < 0.0) axis = -axis;
  face.axis = axis;
  face.point = region.surface.point;
  face.radius = region.surface.radius;
  face.concave = region.concave;
  return face;
}

}  // namespace

Segmentation segmentFaces(const Mesh& mesh, const Adjacency& adjacency, const SegmentationOptions& options) {
  Segmentation out;
  const int n = mesh.triangleCount();
  if (n == 0) return out;
  const Tolerances tol = resolveTolerances(mesh, options);
  const std::vector<Facet> facets = describeFacets(mesh, tol);

  std::vector<int> patch_of;
  const std::vector<PlanarPatch> patches = findPlanarPatches(mesh, adjacency, facets, tol, patch_of);
  const PatchGraph graph = linkPatches(mesh, adjacency, patch_of, static_cast<int>(patches.size()));
  CylinderFinder finder(mesh, patches, graph, tol);
  const std::vector<CylinderRegion> cylinders = finder.find();
  const std::vector<int>& cylinder_of = finder.cylinderOf();
  const std::vector<char> plane = findRealPlanes(patches, graph, cylinder_of, tol);

  std::vector<char> free_form(n, 0);
  for (int t = 0; t < n; ++t) free_form[t] = cylinder_of[patch_of[t]] < 0 && !plane[patch_of[t]];
  int free_form_groups = 0;
  const std::vector<int> group = groupFreeForm(adjacency, free_form, tol, &free_form_groups);

  // Segments are numbered by their first triangle, so the numbering follows the mesh and not the passes.
  const int plane_units = static_cast<int>(patches.size()), cylinder_units = static_cast<int>(cylinders.size());
  std::vector<int> segment_of_unit(plane_units + cylinder_units + free_form_groups, -1);
  out.triangle_face.assign(n, -1);
  for (int t = 0; t < n; ++t) {
    const int p = patch_of[t];
    const int unit = free_form[t] ? plane_units + cylinder_units + group[t]
                     : cylinder_of[p] >= 0 ? plane_units + cylinder_of[p]
                                           : p;
    if (segment_of_unit[unit] < 0) {
      segment_of_unit[unit] = static_cast<int>(out.faces.size());
      out.faces.push_back(free_form[t] ? Face() : cylinder_of[p] >= 0 ? cylinderFace(cylinders[cylinder_of[p]])
                                                                       : planeFace(patches[p]));
    }
    const int segment = segment_of_unit[unit];
    out.triangle_face[t] = segment;
    out.faces[segment].area += facets[t].area;
    ++out.faces[segment].triangle_count;
  }
  return out;
}

}  // namespace art2part
