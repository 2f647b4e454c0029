// Shapes for the planar-region tests (clearing, engagement, slicing): rings in mm.
#pragma once

#include <cmath>

#include "art2part/roughing/region.h"

namespace art2part {
namespace test {

// The axis-aligned rectangle [x0, x1] x [y0, y1], counter-clockwise.
inline Ring rectangle(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// A regular n-gon inscribed in the circle of radius r round c, counter-clockwise.
inline Ring circle(const Point2& c, double r, int n = 72) {
  constexpr double kTwoPi = 6.28318530717958647692;
  Ring ring;
  for (int i = 0; i < n; ++i) ring.push_back(c + r * Point2(std::cos(kTwoPi * i / n), std::sin(kTwoPi * i / n)));
  return ring;
}

}  // namespace test
}  // namespace art2part
