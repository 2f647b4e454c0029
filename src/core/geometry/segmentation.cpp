// Face segmentation of a triangle mesh in three passes:
//  1. planar patches: region growing over manifold edges, each triangle joining the patch whose plane holds its
//     corners and whose normal it shares;
//  2. cylinders and cones (ruled_surfaces.cpp): a tessellation cuts them into planar strips between rulings, so they
//     are grown over patches from seeds of three such strips (or a whole fan round a cone's apex, cone_fans.cpp),
//     every patch checked against the fitted surface; short cylinders that are pieces of an extruded free-form
//     profile are dropped again (extruded_profiles.cpp);
//  3. what is left: a planar patch is a plane unless it is one of a chain of small facets bending gently into each
//     other (a torus, a sphere, a fillet with too few strips, free-form); the facets of such chains are grouped into
//     free-form ("other") segments, split at sharp edges, and those that fit a sphere or a torus become one
//     (doubly_curved.cpp).
#include "art2part/geometry/segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include "segmentation_internal.h"

namespace art2part {
namespace segmentation {

namespace {

Tolerances resolveTolerances(const Mesh& mesh, const SegmentationOptions& options) {
  const double diagonal = boundingBox(mesh).diagonal();
  Tolerances tol;
  // CAD tessellations put vertices on their surface up to the B-rep's own edge tolerance: intersection curves
  // approximated by splines leave boundary vertices up to 3e-5 of the part off a cylinder in NIST CTC 2, so 1e-4.
  // Surfaces that this cannot tell apart (a plane tangent to a fillet) differ in their normals.
  tol.distance = options.distance_tolerance >= 0.0 ? options.distance_tolerance : 1e-4 * diagonal;
  tol.fine_distance = 0.1 * tol.distance;
  // Rounding of positions: float32 in an STL file (6e-8 of the coordinates) and vertex merging (1e-6 of the part).
  tol.noise = 1e-6 * diagonal;
  tol.angle = options.angle_tolerance;
  tol.max_bend = options.max_strip_bend;
  tol.max_radius = 10.0 * diagonal;
  tol.min_strips = std::max(3, options.min_cylinder_strips);
  tol.min_plane_triangles = std::max(1, options.min_plane_triangles);
  return tol;
}

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

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// Pass 1: planar patches.

void PlanarPatch::add(int t, const Facet& f) {
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

namespace {

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
    for (int t : patch.triangles)
      patch.vertices.insert(patch.vertices.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
    std::sort(patch.vertices.begin(), patch.vertices.end());
    patch.vertices.erase(std::unique(patch.vertices.begin(), patch.vertices.end()), patch.vertices.end());
  }
  return patches;
}

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
// Pass 3: planes and free-form.

// A patch of a few triangles that bends gently into another such patch is a facet of a curved surface we do not fit
// (a torus, a fillet of two strips, free-form), not a plane. Big patches and strips of cylinders and cones are
// surfaces already.
std::vector<char> findRealPlanes(const std::vector<PlanarPatch>& patches, const PatchGraph& graph,
                                 const std::vector<int>& ruled_of, const std::vector<char>& curved,
                                 const Tolerances& tol) {
  auto small = [&](int p) { return ruled_of[p] < 0 && (curved[p] || patches[p].size() < tol.min_plane_triangles); };
  std::vector<char> plane(patches.size(), 0);
  for (int p = 0; p < static_cast<int>(patches.size()); ++p) {
    if (ruled_of[p] >= 0 || curved[p] || patches[p].degenerate()) continue;
    bool facet_of_curve = false;
    if (small(p))
      for (int li : graph.links_of[p])
        if (graph.links[li].max_bend <= tol.max_bend && small(graph.links[li].other(p))) facet_of_curve = true;
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

Face ruledFace(const RuledRegion& region) {
  Face face;
  face.concave = region.concave;
  if (region.surface.is_cone) {
    const ConeSurface& cone = region.surface.cone;
    face.type = SurfaceType::Cone;
    face.axis = cone.axis;  // from the apex into the cone, as face.h wants
    face.point = cone.apex;
    face.half_angle = cone.half_angle;
    return face;
  }
  const CylinderSurface& cylinder = region.surface.cylinder;
  face.type = SurfaceType::Cylinder;
  // The sign of a cylinder's axis means nothing: make it canonical (largest component positive) for stable output.
  Eigen::Index largest = 0;
  cylinder.axis.cwiseAbs().maxCoeff(&largest);
  face.axis = cylinder.axis(largest) < 0.0 ? Vec3(-cylinder.axis) : cylinder.axis;
  face.point = cylinder.point;
  face.radius = cylinder.radius;
  return face;
}

// What each triangle ended up in after the passes.
struct Assignment {
  std::vector<int> patch_of;                // pass 1
  std::vector<PlanarPatch> patches;
  std::vector<int> ruled_of;                // pass 2, per patch
  std::vector<RuledRegion> ruled;
  std::vector<char> plane;                  // pass 3, per patch
  std::vector<char> free_form;              // per triangle
  std::vector<int> group;                   // free-form group per triangle
  int groups = 0;
};

// Segments are numbered by their first triangle, so the numbering follows the mesh and not the passes.
Segmentation numberSegments(const std::vector<Facet>& facets, const Assignment& a) {
  const int n = static_cast<int>(facets.size());
  const int plane_units = static_cast<int>(a.patches.size()), ruled_units = static_cast<int>(a.ruled.size());
  std::vector<int> segment_of_unit(plane_units + ruled_units + a.groups, -1);
  Segmentation out;
  out.triangle_face.assign(n, -1);
  for (int t = 0; t < n; ++t) {
    const int p = a.patch_of[t];
    const int region = a.ruled_of[p];
    const int unit = a.free_form[t] ? plane_units + ruled_units + a.group[t] : region >= 0 ? plane_units + region : p;
    if (segment_of_unit[unit] < 0) {
      segment_of_unit[unit] = static_cast<int>(out.faces.size());
      out.faces.push_back(a.free_form[t] ? Face() : region >= 0 ? ruledFace(a.ruled[region]) : planeFace(a.patches[p]));
    }
    const int segment = segment_of_unit[unit];
    out.triangle_face[t] = segment;
    out.faces[segment].area += facets[t].area;
    ++out.faces[segment].triangle_count;
  }
  return out;
}

// Free-form segments that are spheres or tori.
void fitFreeForm(const Mesh& mesh, const Tolerances& tol, Segmentation& out) {
  std::vector<std::vector<int>> triangles(out.faces.size());
  for (int t = 0; t < mesh.triangleCount(); ++t)
    if (out.faces[out.triangle_face[t]].type == SurfaceType::Other) triangles[out.triangle_face[t]].push_back(t);
  for (std::size_t s = 0; s < out.faces.size(); ++s)
    if (!triangles[s].empty()) fitDoublyCurved(mesh, triangles[s], tol, out.faces[s]);
}

}  // namespace
}  // namespace segmentation

Segmentation segmentFaces(const Mesh& mesh, const Adjacency& adjacency, const SegmentationOptions& options) {
  using namespace segmentation;
  const int n = mesh.triangleCount();
  if (n == 0) return Segmentation();
  const Tolerances tol = resolveTolerances(mesh, options);
  const std::vector<Facet> facets = describeFacets(mesh, tol);

  Assignment a;
  a.patches = findPlanarPatches(mesh, adjacency, facets, tol, a.patch_of);
  const PatchGraph graph = linkPatches(mesh, adjacency, a.patch_of, static_cast<int>(a.patches.size()));
  a.ruled = findRuledSurfaces(mesh, a.patches, graph, tol, a.ruled_of);
  // Strips of a curved surface freed from pass 2 are no planes, whatever their size.
  const std::vector<char> curved =
      releaseProfilePieces(RegionContext{mesh, a.patches, graph, tol, a.ruled_of}, a.ruled, a.ruled_of);
  a.plane = findRealPlanes(a.patches, graph, a.ruled_of, curved, tol);
  a.free_form.assign(n, 0);
  for (int t = 0; t < n; ++t) a.free_form[t] = a.ruled_of[a.patch_of[t]] < 0 && !a.plane[a.patch_of[t]];
  a.group = groupFreeForm(adjacency, a.free_form, tol, &a.groups);
  Segmentation out = numberSegments(facets, a);
  fitFreeForm(mesh, tol, out);
  return out;
}

}  // namespace art2part
