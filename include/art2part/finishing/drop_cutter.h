// Drop-cutter: where a tool coming down its axis first touches a mesh. In a frame whose z is the tool axis, for a
// point (x, y) the lowest tip height z at which the tool (ball, bull or flat end mill: its cutting outline, the flutes
// only) lies on or above every triangle: the maximum over the triangles under the tool's footprint of the contact
// height with each triangle's facet, edges and vertices (ball: sphere against each; flat: the disc's rim against edges,
// its face against vertices; bull: the torus, through the offset-ellipse of an edge). Exact up to rounding (no z-map),
// so a pass through drop-cutter points never gouges at its points; between them the chordal refinement of the caller
// keeps the error bounded.
#pragma once

#include <memory>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"

namespace art2part {

class DropCutter {
 public:
  // `vertices` in the tool frame (z up along the tool axis), the mesh's triangles. Triangles are binned on an x-y
  // grid of about the tool's radius, so a query reads only those under the footprint.
  DropCutter(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, const Tool& tool);
  // The tip height at (x, y); `floor` when no triangle lies under the footprint.
  double drop(double x, double y, double floor) const;
  // The same and the triangle touched (-1 when none).
  double drop(double x, double y, double floor, int* triangle) const;
  double radius() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

}  // namespace art2part
