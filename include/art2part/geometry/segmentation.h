// Recovering faces of a mesh: planar regions, cylindrical regions (axis and radius fitted), the rest free-form.
#pragma once

#include <vector>

#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/face.h"
#include "art2part/geometry/mesh.h"

namespace art2part {

struct SegmentationOptions {
  double angle_tolerance = 0.5 * 3.14159265358979323846 / 180.0;  // rad, normal deviation within a plane
  double distance_tolerance = -1.0;  // mm, distance of a vertex to its fitted surface; < 0: 1e-4 x box diagonal
  // rad, largest bend between two neighbouring strips of one tessellated cylinder (8 facets round: 45 degrees).
  double max_strip_bend = 50.0 * 3.14159265358979323846 / 180.0;
  int min_cylinder_strips = 3;  // planar strips a cylinder must have (below: too few to tell from planes)
  // Planar patches of fewer triangles that bend gently into other such patches are facets of a curved surface
  // (cone, free-form), not planes.
  int min_plane_triangles = 3;
};

struct Segmentation {
  std::vector<int> triangle_face;  // segment id of each triangle
  std::vector<Face> faces;         // one per segment, with its fitted surface
};

Segmentation segmentFaces(const Mesh& mesh, const Adjacency& adjacency, const SegmentationOptions& options = {});

// How well a segmentation matches reference faces: a triangle matches when its segment's majority reference face is
// its own face and its face's majority segment is its own segment (a one-to-one match, weighted by triangle count).
// Reference faces on the same surface that share their majority segment count as one face first: a B-rep splits a
// full cylinder into two halves, or a plane into several faces, and no mesh can show such a split.
struct SegmentationScore {
  double matched_fraction = 0.0;   // of all triangles
  double type_agreement = 0.0;     // triangles whose segment type equals their reference face type
  int segments = 0;
  int reference_faces = 0;  // after merging reference faces split on one surface (see segmentation_score.cpp)
};
SegmentationScore scoreSegmentation(const std::vector<int>& segment_of, const std::vector<Face>& segments,
                                    const std::vector<int>& face_of, const std::vector<Face>& faces);

}  // namespace art2part
