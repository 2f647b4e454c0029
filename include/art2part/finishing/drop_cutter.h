// Drop-cutter: where a tool coming down its axis first touches a mesh. In a frame whose z is the tool axis, for a
// point (x, y) the lowest tip height z at which the tool (ball, bull or flat end mill: its cutting outline, the flutes
// only, continued upwards as a cylinder of the cutting radius) lies on or above every triangle: the maximum over the
// triangles under the tool's footprint of the contact height with each triangle's facet, edges and vertices.
//
// The lower surface of each of these tools is the height f(d) above the tip at radial distance d <= R (R the cutting
// radius, r the corner radius, R' = R - r the flat bottom's radius): 0 for d <= R', r - sqrt(r^2 - (d - R')^2) beyond
// (ball: R' = 0, r = R; flat: r = 0, f = 0). The drop is the maximum over mesh points p within the disc of
// p.z - f(|p - (x, y)|):
//  - vertex: that value at the vertex;
//  - facet: the tool's support point towards the plane, P = c - R' u - r n (n the plane's upward normal, u its
//    horizontal part made unit), when P lies inside the triangle; a linear function of (x, y) per triangle;
//  - edge: along a line p.z - f is a linear function minus a convex one (f is convex and nondecreasing in d, d convex
//    along the line), so it is concave and its maximum over the edge is the root of its derivative: closed form for
//    the ball (the circle of radius sqrt(R^2 - a^2) against a line, a the horizontal distance to it), the ends of the
//    disc's chord for the flat, and for the bull (the torus against the line) a safeguarded Newton iteration on the
//    corner angle of the contact, bracketing the root; it stops when |g'(s)| times the bracket's width along the edge
//    is at most kBullContactTolerance, which bounds the error since a concave g has g(s*) <= g(s) + g'(s)(s* - s):
//    the height returned is never above the exact contact and at most kBullContactTolerance below it.
// Exact up to that and rounding (no z-map), so a pass through drop-cutter points never gouges at its points; between
// them the chordal refinement of the caller keeps the error bounded. Edges and vertices shared by several triangles are
// evaluated once (by their lowest-numbered triangle). A drill (pointed) is refused.
//
// Speed: triangles are rasterised into an x-y grid of cells about the tool's radius (a triangle sits in the cells its
// projection meets, not those of its bounding box, so a long sliver costs cells along its length only), each cell's
// triangles sorted by their highest z. A query visits the cells under its footprint and in each stops at the first
// triangle no higher than the best contact so far: on a floor the first triangle decides, on a wall the top edge.
#pragma once

#include <memory>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"

namespace art2part {

// mm: how far below the exact torus-edge contact the bull's drop may come out (see above).
constexpr double kBullContactTolerance = 1e-9;

class DropCutter {
 public:
  // `vertices` in the tool frame (z up along the tool axis), the mesh's triangles (degenerate ones are harmless: their
  // edges and vertices still count). Throws InputError for a drill or a tool checkTool refuses.
  DropCutter(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, const Tool& tool);
  // The tip height at (x, y); `floor` when no triangle lies under the footprint (or all lie lower). Thread-safe.
  double drop(double x, double y, double floor) const;
  // The same and the triangle touched (-1 when none).
  double drop(double x, double y, double floor, int* triangle) const;
  double radius() const;         // R, the cutting radius
  double cornerRadius() const;   // r: R for a ball, 0 for a flat
  // The lower surface's height above the tip at radial distance d (0 <= d <= R): f(d) above.
  double profile(double d) const;
  Box bounds() const;            // of the vertices, in the tool frame
  long binnedEntries() const;    // triangle entries over all cells (a triangle counts once per cell it meets)

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

}  // namespace art2part
