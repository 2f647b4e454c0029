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

// One way to finish a face: a strategy from a direction in a setup.
struct FinishingChoice {
  FinishingKind kind = FinishingKind::Surface3Axis;
  int setup = -1;
  Vec3 direction = Vec3::Zero();   // the tool axis, part frame
  int hole = -1;                   // Drill, Helix: index into the holes
  double depth = 0;                // SideMill, Contour: the face's extent along the direction, mm
  bool whole = true;               // the direction sees the whole face (visibility); the planner judges the reach
  std::string note;                // why this is not the shape's first choice ("square to no setup direction: ...")
};

struct FaceAssignment {
  int face = -1;
  // In order of preference; the planner takes the first and, when it reaches little of the face, the next.
  std::vector<FinishingChoice> choices;
  std::string reason;              // no choice at all: why
};

// One per face of the part, by face id. `longest_flutes`: the longest flute length of the library's flat end mills.
// Choices in order: a hole's drill or helix; a plane's face milling from a setup that sees it whole, side milling
// (least depth first, within the flutes), face milling from one that sees only part of it; a cylinder's contour
// likewise; then surface finishing from the setups that meet the face most squarely (at most three).
std::vector<FaceAssignment> assignFaces(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                        const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods,
                                        double longest_flutes, const FinishingOptions& options);

}  // namespace art2part
