// Faces of a part: B-rep faces of a STEP file, or regions recovered from a mesh by segmentation.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

enum class SurfaceType { Plane, Cylinder, Cone, Sphere, Torus, Other };

const char* surfaceTypeName(SurfaceType type);  // "plane", "cylinder", ... "other"

// One face and the analytic surface it lies on. Which fields mean something depends on the type:
//  plane:    normal (outward unit normal), offset (normal . x = offset)
//  cylinder: axis (unit), point (on the axis), radius, concave (true for a hole, false for a boss)
//  cone:     axis (unit, from the apex into the cone), point (apex), half_angle (rad), concave
//  sphere:   point (centre), radius, concave
//  torus:    axis (unit), point (centre), radius (major), minor_radius, concave
//  other:    free-form; nothing but area and triangles
struct Face {
  SurfaceType type = SurfaceType::Other;
  Vec3 normal = Vec3::Zero();
  double offset = 0.0;
  Vec3 axis = Vec3::Zero();
  Vec3 point = Vec3::Zero();
  double radius = 0.0;
  double minor_radius = 0.0;
  double half_angle = 0.0;
  bool concave = false;
  double area = 0.0;       // mm^2, of the face's triangles
  int triangle_count = 0;  // how many triangles of the mesh carry this face's id
};

// Where a part's faces come from.
enum class FaceSource { BRep, Segmentation };

struct FaceCounts {
  int plane = 0, cylinder = 0, cone = 0, sphere = 0, torus = 0, other = 0;
  int total() const { return plane + cylinder + cone + sphere + torus + other; }
};
FaceCounts countFaces(const std::vector<Face>& faces);

// Recomputes each face's area and triangle count from the mesh and the triangle -> face map.
void updateFaceAreas(const Mesh& mesh, const std::vector<int>& triangle_face, std::vector<Face>& faces);

// How far each face's triangles reach past its true surface into the space the surface bounds: a concave curved face
// (a hole, a spherical or toroidal pocket, a concave cone) is tessellated by chords inside its circles, so the mesh's
// material stands proud of the true surface by up to the chords' sag there, and a tool cutting the true surface cuts
// that deep into the mesh. The largest over the face's triangles' centroids and edge midpoints, 0 for planes, convex
// faces (their chords lie in the material: a tool on the true surface leaves the sag instead) and free-form faces.
std::vector<double> concaveSag(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<Face>& faces);

}  // namespace art2part
