// Internals shared by the passes of face segmentation (segmentation.cpp, ruled_surfaces.cpp and the files they use);
// not library interface.
#pragma once

#include <utility>
#include <vector>

#include "art2part/common/angles.h"
#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/face.h"
#include "art2part/geometry/mesh.h"
#include "art2part/geometry/surface_fit.h"

namespace art2part {
namespace segmentation {

// The options resolved for one mesh.
struct Tolerances {
  double distance = 0.0;       // mm: how far a vertex may lie from its fitted surface
  double fine_distance = 0.0;  // mm: the same where the data shows no more is needed (cylinders, cones)
  double noise = 0.0;       // mm: rounding of vertex positions, which turns the normals of small triangles
  double angle = 0.0;       // rad: normal deviation within a plane
  double max_bend = 0.0;    // rad: largest bend between two strips of one tessellated curved surface
  double max_radius = 0.0;  // mm: a larger "cylinder" is a gently bent sheet, not a feature
  int min_strips = 3;
  int min_plane_triangles = 3;
};

// What one triangle contributes to a fit.
struct Facet {
  Vec3 normal = Vec3::Zero();
  Vec3 centroid = Vec3::Zero();
  double area = 0.0;
  double normal_slack = kPi;  // rad: how far rounding of its corners may turn the normal (all the way if degenerate)
};

// Pass 1 finds these: connected triangles on one plane.
struct PlanarPatch {
  std::vector<int> triangles;
  std::vector<int> vertices;        // distinct
  Vec3 area_vector = Vec3::Zero();  // sum of area x normal: its direction is the area-weighted normal
  Vec3 moment = Vec3::Zero();       // sum of area x centroid
  double area = 0.0;
  double normal_slack = kPi;  // of its most reliable triangle
  Vec3 normal = Vec3::Zero();
  double offset = 0.0;

  Vec3 centroid() const { return area > 0.0 ? Vec3(moment / area) : Vec3::Zero(); }
  bool degenerate() const { return normal.norm() == 0.0; }
  int size() const { return static_cast<int>(triangles.size()); }
  void add(int t, const Facet& f);
};

// Which patches touch across manifold edges, along which edges, and how sharply they bend there.
struct PatchLink {
  int a = -1, b = -1;
  std::vector<std::pair<int, int>> edges;  // vertex ids
  double max_bend = 0.0;                   // rad, largest |dihedral| along the shared edges
  int other(int p) const { return p == a ? b : a; }
};

struct PatchGraph {
  std::vector<PatchLink> links;
  std::vector<std::vector<int>> links_of;  // per patch
};

// A cylinder or a cone: the surfaces a tessellation cuts into planar strips between straight rulings.
struct RuledSurface {
  bool is_cone = false;
  CylinderSurface cylinder;
  ConeSurface cone;

  const Vec3& axis() const { return is_cone ? cone.axis : cylinder.axis; }
  double distance(const Vec3& p) const;
  Vec3 radial(const Vec3& p) const;  // unit, from the axis towards p, square to the axis
  Vec3 normal(const Vec3& p) const;  // unit normal of the surface near p, pointing away from the axis
  Vec3 ruling(const Vec3& p) const;  // unit direction of the ruling nearest p
};

// Pass 2 finds these: patches that are the strips of one cylinder or cone.
struct RuledRegion {
  std::vector<int> patches;
  RuledSurface surface;
  bool concave = false;     // outward normals point towards the axis (a hole, a countersink)
  double span_limit = 0.0;  // rad: widest patch around the axis it takes, from its seed strips
  double tolerance = 0.0;   // mm: how far its vertices may lie from the surface, from its seed
};

// What the tests on a ruled region look at: the mesh, its patches and which region each patch is in.
struct RegionContext {
  const Mesh& mesh;
  const std::vector<PlanarPatch>& patches;
  const PatchGraph& graph;
  const Tolerances& tol;
  const std::vector<int>& region_of;  // per patch, -1 for none
};

// Whether region id is a band of a doubly curved surface of revolution (torus, sphere) rather than a cylinder or a
// cone face: it bends gently into unfitted facets at both ends (ruled_region_ends.cpp).
bool bandOfRevolution(const RegionContext& context, const RuledRegion& region, int id);

// Cones tessellated as a fan of strips round a vertex at their apex, fitted from the strips' planes: seeds for pass 2
// that three strips alone would not give (cone_fans.cpp). The regions are not yet grown.
std::vector<RuledRegion> findConeFans(const Mesh& mesh, const std::vector<PlanarPatch>& patches,
                                      const Tolerances& tol);

// ruled_of[p]: the region of patch p, or -1.
std::vector<RuledRegion> findRuledSurfaces(const Mesh& mesh, const std::vector<PlanarPatch>& patches,
                                           const PatchGraph& graph, const Tolerances& tol,
                                           std::vector<int>& ruled_of);

// Drops the cylinders that are pieces of an extruded free-form profile (extruded_profiles.cpp): their regions are
// emptied and their patches freed (ruled_of -1). Returns per patch whether it was freed: a strip of a curved
// surface, never a plane.
std::vector<char> releaseProfilePieces(const RegionContext& context, std::vector<RuledRegion>& regions,
                                       std::vector<int>& ruled_of);

// A free-form segment's triangles as a sphere or a torus, when one fits them all within the tolerance: sets the
// face's type and surface; leaves it free-form otherwise (doubly_curved.cpp).
void fitDoublyCurved(const Mesh& mesh, const std::vector<int>& triangles, const Tolerances& tol, Face& face);

}  // namespace segmentation
}  // namespace art2part
