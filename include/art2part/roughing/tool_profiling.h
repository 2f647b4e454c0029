// Profiling (thesis 4.1.3.2): selecting a tool and tweaking its orientation at a machining point. The tool - flutes,
// shank and holder, each a cylinder (a sphere and a cylinder for a ball end) grown by a margin - is posed at the
// point along the proposed axis and tested against the part with FCL (an OBBRSS tree of the part's triangles, built
// once). Where it collides, the contacts are binned into zones round the tool by the azimuth of the part's normal
// there; each zone's deepest
// penetration at its height above the tip asks for a tilt of atan(penetration / lever) away from it, and the tilts of
// the zones are composed. The machining point stays the tool's lowest point along the reach axis: as the thesis
// says, the tool is pushed along its axis to keep the machining plane (a flat end tilted by theta would otherwise dip
// r sin(theta) under it). When two opposite zones both penetrate there is no
// escape: the next smaller tool is tried. A posture beyond the machine's tilt from the reach axis, or no clear
// posture after a few iterations with any tool, leaves the point dead.
#pragma once

#include <memory>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"

namespace art2part {

struct ProfileContact {
  Vec3 point = Vec3::Zero();   // where the tool meets the part
  Vec3 normal = Vec3::UnitZ(); // the outward normal of the part's triangle met
  double depth = 0;            // penetration (mm)
  double height = 0;           // above the tip along the axis (mm)
  ToolZone zone = ToolZone::Flutes;
};

class PartCollider {
 public:
  explicit PartCollider(const Mesh& part);
  ~PartCollider();
  PartCollider(const PartCollider&) = delete;
  PartCollider& operator=(const PartCollider&) = delete;

  // Whether the tool at `pose` (flutes grown by flute_margin, sideways and below the tip; shank and holder by
  // body_margin) meets no triangle of the part. `contacts`, if given, receives where it does (up to 64).
  bool toolClear(const Tool& tool, const ToolPose& pose, double flute_margin, double body_margin,
                 std::vector<ProfileContact>* contacts = nullptr) const;

 private:
  struct Model;
  std::unique_ptr<Model> model_;
};

struct ProfileOptions {
  double flute_margin = 0.3;   // the finishing allowance
  double body_margin = 0.5;    // kept between shank or holder and the part
  int max_iterations = 8;
  double max_tilt_deg = 110;   // from the reach axis
  int zones = 8;
};

struct Posture {
  bool live = false;
  int tool = -1;               // index into the tools given
  ToolPose pose;               // the tip pushed along the axis from the machining point
  int iterations = 0;
};

// Pseudo code 2 of the thesis: `tools` largest first, `proposed` the machining point and its access direction.
Posture profileTool(const PartCollider& part, const std::vector<const Tool*>& tools, const ToolPose& proposed,
                    const Vec3& reach_axis, const ProfileOptions& options = {});

}  // namespace art2part
