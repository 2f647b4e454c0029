// Internal to the holes of the finishing stage: geometry the recognition, the method choice and the paths share.
#pragma once

#include <limits>
#include <vector>

#include "art2part/common/angles.h"
#include "art2part/finishing/holes.h"

namespace art2part::hole_detail {

constexpr double kDegree = kPi / 180;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// A drill with this point angle (within the point tolerance) is a spot drill: it centres and chamfers, it makes no hole.
constexpr double kSpotPointAngleDeg = 90;

// Two unit vectors orthogonal to `axis` (unit) and to each other.
void orthonormalPair(const Vec3& axis, Vec3& u, Vec3& v);

// Least distance of the part's material from the line through `start` along `dir` (unit), in bands of `step` along
// dir: band k holds heights (p - start) . dir in [k step, (k + 1) step], only heights above `slack` count; infinity
// where no material lies within `cap` of the line. Exact per triangle (each clipped to the band, its projection's
// distance to the line).
std::vector<double> radialBands(const Mesh& mesh, const Vec3& start, const Vec3& dir, double step, int count,
                                double cap, double slack);

// Fills free_radius, clearance_step and free_beyond of a hole whose axis, mouth, diameter, total depth and bottom are
// set (radialBands over the part's mesh).
void measureSurroundings(const Part& part, Hole& hole, const HoleOptions& options);

// The hole's radius at `depth` below the mouth: the widest of its segments there (a cylinder's radius, a cone's or a
// torus's interpolated, a flat's outer radius); 0 where none is.
double holeRadiusAt(const Hole& hole, double depth);

// The length of a drill's point (its cone), mm.
double pointLength(const Tool& drill);

}  // namespace art2part::hole_detail
