// Which strategy, setup and tool direction finishes each face (thesis 4.3: "the entire face must be machined from the
// same direction, in the same setup"). For each face, the strategies its shape admits (admissible.h), tried in order
// of preference among the directions the plan offers (3-axis: the setup directions; 5-axis: also the face's own
// direction - a plane's normal, a cylinder's axis - when a setup's tilt reaches it), a direction counting only when the
// face's visibility cone holds it (permissible):
//   hole a drill or a helix makes     Drill / Helix along the hole's axis
//   plane                             FaceMill along its normal; else SideMill from the direction parallel to it with
//                                     the least depth (the face's extent along it), if the flutes of some flat end
//                                     mill reach that depth; else as a surface
//   cylinder (and its extrusions)     Contour along its axis (either sense)
//   anything else, or what failed     Surface3Axis from the setup that meets the face most squarely (the largest
//                                     least n . d over its normals), or Surface5Axis in 5-axis mode
// A face no direction reaches is unmachinable: "no permissible direction".
#pragma once

#include <string>
#include <vector>

#include "art2part/finishing/finishing.h"

namespace art2part {

struct FaceAssignment {
  int face = -1;
  FinishingKind kind = FinishingKind::Surface3Axis;
  int setup = -1;                  // -1: none (unmachinable)
  Vec3 direction = Vec3::Zero();   // the tool axis, part frame (zero: none)
  int hole = -1;                   // Drill, Helix: index into the holes
  double depth = 0;                // SideMill, Contour: the face's extent along the direction, mm
  bool whole = true;               // the direction sees the whole face (surface finishing may take a face it sees in part)
  std::string note;                // why not the first choice ("square to no setup direction", "42 mm deep: ...")
  std::string reason;              // setup == -1: why no direction
};

// One per face of the part, by face id. `longest_flutes`: the longest flute length of the library's flat end mills.
std::vector<FaceAssignment> assignFaces(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                        const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods,
                                        double longest_flutes, const FinishingOptions& options);

}  // namespace art2part
