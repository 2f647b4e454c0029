// What the toolpath left: stock outside the part, how thick, where, and the cusps on each face.
//
// Thickness at a point of leftover is estimated from the dexels alone: along each family's ray through it, the
// distance to the part's surface met on either side times |n . ray| (n the surface normal there: the distance to that
// face's tangent plane, exact for a plane whatever the ray's angle), the least over the three families; crossings
// more grazing than 75 degrees are ignored. Where no ray meets the part, the distance to the part's box stands in.
// A region is a connected set of leftover spans of the z family (spans on 4-neighbour rays that overlap), so a rest
// pass can take its box and volume. Cusp (scallop) height of a face: the leftover thickness met just outside the
// face along rays within 60 degrees of its normal, as max and mean over those samples: for a finishing pass, the
// scallop left; for an untouched face, the stock on it.
#pragma once

#include <vector>

#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/stock.h"

namespace art2part {

struct LeftoverRegion {
  double volume_mm3 = 0;
  double max_thickness_mm = 0;
  Vec3 thickest_point = Vec3::Zero();
  Box box;
};

struct FaceCusp {
  int face = -1;
  double max_mm = 0, mean_mm = 0;  // leftover thickness over the face's samples
  int samples = 0;                 // rays crossing the face within 60 degrees of its normal
};

struct LeftoverAnalysis {
  double volume_mm3 = 0;        // mean over the three families
  double max_thickness_mm = 0;
  std::vector<LeftoverRegion> regions;  // largest volume first
  std::vector<FaceCusp> faces;          // by face id, faces with samples only
};

// `triangle_face` gives the face of each part triangle (empty: no per-face cusps). Spans thinner than `noise_mm` along
// their ray are rounding, not leftover.
LeftoverAnalysis analyseLeftover(const Stock& stock, const MeshDexels& part, const Box& part_box,
                                 const std::vector<int>& triangle_face, double noise_mm = 1e-6);

}  // namespace art2part
