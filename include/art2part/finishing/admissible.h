// Admissible and permissible tool directions of a face (thesis 4.2). How a face can be finished depends on its shape
// and the tool, not only on access:
//   0-DOF  face milling along a plane's normal; drilling or peripheral milling along a hole's or cylinder's axis
//   1-DOF  side milling of a plane: any direction in the plane (the great circle square to its normal)
//   2-DOF  ball or bull end milling: any direction that sees every point of the face from its front (n . d >= 0 for
//          every normal n of the face): on the sphere, the intersection of the hemispheres of its normals
// Permissible = admissible and accessible (the face's visibility cone: directions that see it whole).
// Edge conditions restrict them further: a concave sharp edge is made exactly only by a flat end mill lying in the
// plane of one of its two faces (the flank makes one, the bottom the other); a concave fillet or hole of radius r only
// by a tool whose corner radius (a flat mill's radius when it works along the fillet's axis) is at most r; convex
// edges restrict nothing.
#pragma once

#include <vector>

#include "art2part/finishing/finishing.h"
#include "art2part/geometry/part.h"
#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/cones.h"

namespace art2part {

enum class Freedom { Zero, One, Two };

struct AdmissibleSet {
  FinishingKind kind = FinishingKind::Surface3Axis;
  Freedom freedom = Freedom::Two;
  // Zero: the direction (a plane's outward normal; a cylinder's axis, `both_senses`). One: the normal of the great
  // circle (a plane's normal). Two: unused (see `normals`).
  Vec3 axis = Vec3::UnitZ();
  bool both_senses = false;
  std::vector<Vec3> normals;  // Two: the face's distinct normals (within about half a degree), unit
};

// Whether `d` (unit) is admissible within `tolerance` radians.
bool admits(const AdmissibleSet& set, const Vec3& d, double tolerance);

// The sets of the strategies a face's shape allows with milling tools: FaceMill and SideMill for a plane, Contour for
// a cylinder (concave or convex), and always Surface3Axis (2-DOF, ball or bull). Drilling comes from holes.h.
// `triangles`: the face's triangles.
std::vector<AdmissibleSet> admissibleSets(const Part& part, int face, const std::vector<int>& triangles);

// The sampled directions of `directions` a set admits, as a cone; permissible: and accessible (`accessible`, the face's
// common visibility cone).
Cone admissibleCone(const AdmissibleSet& set, const DirectionSet& directions, double tolerance);
Cone permissibleCone(const AdmissibleSet& set, const DirectionSet& directions, const Cone& accessible, double tolerance);

// An edge of a face with a neighbouring face, for the edge conditions.
struct EdgeCondition {
  int neighbour = -1;               // face across the edge (-1: boundary)
  EdgeClass klass = EdgeClass::Smooth;
  std::vector<Vec3> normals;            // the face's outward normals along the edge (distinct within half a degree)
  std::vector<Vec3> neighbour_normals;  // the neighbour's
  double length_mm = 0;             // total length of the edge between the two faces
};

// The edges of a face with each neighbouring face (sharp ones classed convex or concave by the adjacency's sharp
// angle, others smooth), longest first.
std::vector<EdgeCondition> edgeConditions(const Part& part, int face, const std::vector<int>& triangles);

// Whether a flat end mill along `d` makes a concave sharp edge exactly: d lies in the tangent plane of one of the two
// faces all along the edge (a curved face: d along its rulings there, e.g. a cylinder's axis).
bool flatMillMakesEdge(const EdgeCondition& edge, const Vec3& d, double tolerance);

// The largest corner radius (ball: radius; bull: corner radius; flat end mill working along a cylinder's axis: its
// radius) that finishes the face's concave curvature: a concave cylinder's, sphere's or torus's radius (the torus's
// minor radius), infinity for a face with no concave curvature. Mesh faces of type Other: estimated from the mesh
// (the least radius of concave bending between neighbouring triangles of the face), infinity when flat or convex.
double concaveRadius(const Part& part, int face, const std::vector<int>& triangles);

// The sampled direction closest to `d` if within `tolerance` radians (special directions sit exactly on plane normals
// and axes), else -1.
int sampledDirection(const DirectionSet& directions, const Vec3& d, double tolerance);

// The extent of the triangles along `d` (unit): a face's depth seen from d.
double extentAlong(const Mesh& mesh, const std::vector<int>& triangles, const Vec3& d);

}  // namespace art2part
