// The tool as the simulation sweeps it: a stack of convex solids of revolution ("pieces") around the tool axis, each a
// cone frustum (cylinders and drill points are frustums) or a zone of a sphere (ball end), tagged with its ToolZone.
// Built from the Tool's fields; the outline is the one `toolRadiusAt` describes (test_simulation checks the two agree).
// A bull end mill's torus corner is a stack of frustums inscribed within `chord_tolerance` of the true arc (the torus
// is the one shape whose ray intersection is a quartic). Every piece is convex, so a ray meets it in one interval.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/simulation/dexel.h"
#include "art2part/tooling/tool.h"

namespace art2part {

struct ToolPiece {
  ToolZone zone = ToolZone::Flutes;
  double h0 = 0, h1 = 0;           // heights above the tip along the axis, h0 < h1
  double r0 = 0, r1 = 0;           // frustum: radius at h0 and h1 (max radius for a sphere zone)
  bool sphere = false;             // sphere zone: centre at height centre_h, radius sphere_radius, cut to [h0, h1]
  double centre_h = 0, sphere_radius = 0;

  double maxRadius() const { return r0 > r1 ? r0 : r1; }
  double radiusAt(double h) const;  // the outline within [h0, h1]
};

struct ToolSolid {
  std::vector<ToolPiece> pieces;  // bottom to top
  double length = 0;              // tip to the top of the highest piece
  double max_radius = 0;
  double radiusAt(double h) const;  // 0 outside the tool
};

// Throws InputError (checkTool) for a tool that cannot exist.
ToolSolid toolSolid(const Tool& tool, double chord_tolerance = 0.001);

// A piece at a pose, prepared for the rays of one family: what depends on the ray alone is a few products and one
// root, the rest is computed once per pose.
class PieceOnRays {
 public:
  PieceOnRays(const ToolPiece& piece, const ToolPose& pose, int axis);
  // The interval of t where the ray at lattice coordinates (u, v) (t along the family's axis) lies inside the piece.
  bool span(double u, double v, Span& out) const;

 private:
  const ToolPiece* piece_;
  double au_, av_, hd_, inv_hd_, tu_, tv_, tk_, wk_;
  double qa_, slope_, rho1_;
};

// The same for one ray: origin + t * e_axis (origin[axis] is ignored, t is the coordinate along the axis).
bool rayPieceSpan(const ToolPiece& piece, const ToolPose& pose, const Vec3& origin, int axis, Span& out);

// The piece swept `rise` mm up its own axis is the piece and this cylinder on top of it (every piece widens upwards
// or keeps its radius, so the widest section is the top one).
ToolPiece risePiece(const ToolPiece& piece, double rise);

// How deep a point inside the piece lies below its surface (radially, or from its end faces): 0 outside.
double penetrationDepth(const ToolPiece& piece, const ToolPose& pose, const Vec3& point);
// The deepest such point on the segment [lo, hi] of the ray (sampled at its ends, middle and nearest the axis).
double deepestOnSpan(const ToolPiece& piece, const ToolPose& pose, const Vec3& origin, int axis, Span segment,
                     Vec3* where = nullptr);

// Axis-aligned box of the piece at the pose.
Box pieceBox(const ToolPiece& piece, const ToolPose& pose);

}  // namespace art2part
