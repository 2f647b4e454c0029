#include "feed_moves.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace art2part::simulation_detail {

namespace {

double pointSegmentDistance2(double h, double r, double h0, double r0, double h1, double r1) {
  const double dh = h1 - h0, dr = r1 - r0, length2 = dh * dh + dr * dr;
  const double f = length2 > 0 ? std::clamp(((h - h0) * dh + (r - r0) * dr) / length2, 0.0, 1.0) : 0.0;
  const double eh = h - (h0 + f * dh), er = r - (r0 + f * dr);
  return eh * eh + er * er;
}

// Slope dr/dh of the outline at the bottom and at the top of a piece.
double slopeAt(const ToolPiece& p, bool top) {
  if (!p.sphere) return p.h1 > p.h0 ? (p.r1 - p.r0) / (p.h1 - p.h0) : 0.0;
  const double h = top ? p.h1 : p.h0, r = p.radiusAt(h);
  return r > 0 ? -(h - p.centre_h) / r : 1e300;
}

bool convexStack(const std::vector<ToolPiece>& pieces) {
  if (pieces.empty() || pieces.front().h0 != 0.0) return false;
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    const ToolPiece &below = pieces[i - 1], &above = pieces[i];
    if (std::abs(above.h0 - below.h1) > 1e-9) return false;
    if (std::abs(above.radiusAt(above.h0) - below.radiusAt(below.h1)) > 1e-9) return false;
    if (slopeAt(above, false) > slopeAt(below, true) + 1e-9) return false;
  }
  return true;
}

}  // namespace

double Flutes::distance(double h, double rho) const {
  double best = 1e300;
  for (const ToolPiece& piece : pieces) best = std::min(best, distanceToPiece(piece, h, rho));
  return best;
}

std::vector<Flutes> flutesOf(const std::vector<Tool>& tools) {
  std::vector<Flutes> result;
  for (const Tool& tool : tools) {
    Flutes f;
    f.h_min = 1e300;
    f.h_max = -1e300;
    for (const ToolPiece& piece : toolSolid(tool).pieces) {
      if (piece.zone != ToolZone::Flutes) continue;
      f.pieces.push_back(piece);
      f.h_min = std::min(f.h_min, piece.h0);
      f.h_max = std::max(f.h_max, piece.h1);
      f.radius = std::max(f.radius, piece.maxRadius());
    }
    if (f.pieces.empty()) f.h_min = f.h_max = 0;
    f.convex = convexStack(f.pieces);
    result.push_back(std::move(f));
  }
  return result;
}

std::vector<FeedMove> feedMoves(const Toolpath& path, const std::vector<Tool>& tools, const std::string& who) {
  std::map<std::string, int> index;
  for (int i = 0; i < static_cast<int>(tools.size()); ++i) index.emplace(tools[i].id, i);
  std::vector<FeedMove> moves;
  for (int row = 0; row < static_cast<int>(path.size()); ++row) {
    const CutterLocation& c = path[row];
    const auto found = index.find(c.tool);
    if (found == index.end())
      throw InputError(who + ": toolpath row " + std::to_string(row) + " uses tool '" + c.tool +
                       "', which the tools do not have");
    if (row == 0 || c.move != MoveKind::Feed) continue;
    const CutterLocation& before = path[row - 1];
    if (before.tool != c.tool || before.setup != c.setup) continue;
    FeedMove m;
    m.tool = found->second;
    m.row = row;
    m.from = {before.tip, before.axis.normalized()};
    m.to = {c.tip, c.axis.normalized()};
    m.angle = std::acos(std::clamp(m.from.axis.dot(m.to.axis), -1.0, 1.0));
    moves.push_back(m);
  }
  return moves;
}

int poseSteps(const FeedMove& move, const Flutes& flutes, double step) {
  const double travel = (move.to.tip - move.from.tip).norm() + move.angle * std::max(std::abs(flutes.h_max), 0.0);
  return std::max(1, static_cast<int>(std::ceil(travel / step - 1e-9)));
}

ToolPose poseAt(const FeedMove& move, double f) {
  ToolPose pose;
  pose.tip = move.from.tip + f * (move.to.tip - move.from.tip);
  if (move.angle < 1e-9) {
    pose.axis = move.from.axis;
    return pose;
  }
  Vec3 across = move.to.axis - move.from.axis.dot(move.to.axis) * move.from.axis;
  if (across.norm() < 1e-12) across = move.from.axis.unitOrthogonal();  // opposite axes: any plane
  across.normalize();
  pose.axis = (std::cos(f * move.angle) * move.from.axis + std::sin(f * move.angle) * across).normalized();
  return pose;
}

Box flutesBox(const Flutes& f, const ToolPose& pose, double grow) {
  Box box;
  const Vec3 extent = (Vec3::Ones() - pose.axis.cwiseProduct(pose.axis)).cwiseMax(0.0).cwiseSqrt() * f.radius;
  for (double h : {f.h_min, f.h_max}) {
    const Vec3 c = pose.tip + h * pose.axis;
    box.extend(c - extent - Vec3::Constant(grow));
    box.extend(c + extent + Vec3::Constant(grow));
  }
  return box;
}

Box moveBox(const FeedMove& move, const Flutes& flutes, double step) {
  Box box = flutesBox(flutes, move.from, 0.0);
  if (move.angle < 1e-9) {
    const Box end = flutesBox(flutes, move.to, 0.0);
    box.extend(end.min);
    box.extend(end.max);
    return box;
  }
  const double reach = std::hypot(std::max(std::abs(flutes.h_min), std::abs(flutes.h_max)), flutes.radius);
  const int steps = std::max(1, static_cast<int>(std::ceil(((move.to.tip - move.from.tip).norm() + move.angle * reach) / step)));
  for (int k = 1; k <= steps; ++k) {
    const Box at = flutesBox(flutes, poseAt(move, static_cast<double>(k) / steps), step);
    box.extend(at.min);
    box.extend(at.max);
  }
  box.extend(box.min - Vec3::Constant(step));
  box.extend(box.max + Vec3::Constant(step));
  return box;
}

double distanceToPiece(const ToolPiece& p, double h, double rho) {
  if (p.sphere) {
    const double c = p.centre_h, R = p.sphere_radius;
    const double dc = std::hypot(h - c, rho);
    const bool in_slab = h >= p.h0 && h <= p.h1;
    if (in_slab && dc <= R) return 0.0;
    double best2 = 1e300;
    // The arc, where the point's radial projection onto the circle falls inside the slab.
    if (dc > 0) {
      const double hq = c + R * (h - c) / dc;
      if (hq >= p.h0 && hq <= p.h1) best2 = (dc - R) * (dc - R);
    }
    // The two chords that cut the disc (their ends are the arc's ends).
    for (double hk : {p.h0, p.h1}) {
      const double w = std::sqrt(std::max(0.0, R * R - (hk - c) * (hk - c)));
      best2 = std::min(best2, pointSegmentDistance2(h, rho, hk, 0.0, hk, w));
    }
    return std::sqrt(best2);
  }
  if (h >= p.h0 && h <= p.h1 && rho <= p.radiusAt(h)) return 0.0;
  double best2 = pointSegmentDistance2(h, rho, p.h0, 0.0, p.h0, p.r0);
  best2 = std::min(best2, pointSegmentDistance2(h, rho, p.h1, 0.0, p.h1, p.r1));
  best2 = std::min(best2, pointSegmentDistance2(h, rho, p.h0, p.r0, p.h1, p.r1));
  return std::sqrt(best2);
}

}  // namespace art2part::simulation_detail
