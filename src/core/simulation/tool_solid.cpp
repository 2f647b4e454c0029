#include "art2part/simulation/tool_solid.h"

#include <algorithm>
#include <cmath>

#include "art2part/common/angles.h"

namespace art2part {

namespace {

ToolPiece frustum(ToolZone zone, double h0, double h1, double r0, double r1) {
  ToolPiece p;
  p.zone = zone;
  p.h0 = h0;
  p.h1 = h1;
  p.r0 = r0;
  p.r1 = r1;
  return p;
}

// A bull mill's corner: the arc from the flat bottom (radius R - rc at h = 0) to the side (radius R at h = rc),
// inscribed by chords whose sagitta stays below the tolerance.
void addTorusCorner(std::vector<ToolPiece>& pieces, double radius, double corner, double chord_tolerance) {
  const double step = 2.0 * std::acos(std::max(0.0, 1.0 - chord_tolerance / corner));
  const int segments = std::clamp(static_cast<int>(std::ceil(0.5 * kPi / std::max(step, 1e-3))), 2, 64);
  const double inner = radius - corner;
  for (int i = 0; i < segments; ++i) {
    const double a0 = 0.5 * kPi * i / segments, a1 = 0.5 * kPi * (i + 1) / segments;
    pieces.push_back(frustum(ToolZone::Flutes, corner * (1 - std::cos(a0)), corner * (1 - std::cos(a1)),
                             inner + corner * std::sin(a0), inner + corner * std::sin(a1)));
  }
}

void addTip(std::vector<ToolPiece>& pieces, const Tool& tool, double chord_tolerance) {
  const double radius = 0.5 * tool.diameter;
  if (tool.type == ToolType::Ball) {
    ToolPiece p = frustum(ToolZone::Flutes, 0.0, std::min(radius, tool.flute_length), radius, radius);
    p.sphere = true;
    p.centre_h = p.sphere_radius = radius;
    pieces.push_back(p);
  } else if (tool.type == ToolType::Bull && tool.corner_radius > 0.0) {
    addTorusCorner(pieces, radius, std::min(tool.corner_radius, radius), chord_tolerance);
  } else if (tool.type == ToolType::Drill) {
    const double half_angle = 0.5 * tool.point_angle_deg * kPi / 180.0;
    pieces.push_back(frustum(ToolZone::Flutes, 0.0, radius / std::tan(half_angle), 0.0, radius));
  }
}

}  // namespace

double ToolPiece::radiusAt(double h) const {
  if (h < h0 || h > h1) return 0.0;
  if (sphere) return std::sqrt(std::max(0.0, sphere_radius * sphere_radius - (h - centre_h) * (h - centre_h)));
  return h1 > h0 ? r0 + (r1 - r0) * (h - h0) / (h1 - h0) : std::max(r0, r1);
}

double ToolSolid::radiusAt(double h) const {
  double r = 0.0;
  for (const ToolPiece& p : pieces) r = std::max(r, p.radiusAt(h));
  return r;
}

ToolSolid toolSolid(const Tool& tool, double chord_tolerance) {
  checkTool(tool);
  ToolSolid solid;
  const double radius = 0.5 * tool.diameter;
  addTip(solid.pieces, tool, chord_tolerance);
  const double tip_top = solid.pieces.empty() ? 0.0 : solid.pieces.back().h1;
  if (tool.flute_length > tip_top)
    solid.pieces.push_back(frustum(ToolZone::Flutes, tip_top, tool.flute_length, radius, radius));
  const double shank = tool.shank_diameter > 0.0 ? 0.5 * tool.shank_diameter : radius;
  if (tool.stickout > tool.flute_length)
    solid.pieces.push_back(frustum(ToolZone::Shank, tool.flute_length, tool.stickout, shank, shank));
  double h = tool.stickout;
  for (const HolderStep& s : tool.holder) {
    if (s.length > 0.0) solid.pieces.push_back(frustum(ToolZone::Holder, h, h + s.length, 0.5 * s.diameter, 0.5 * s.diameter));
    h += s.length;
  }
  for (const ToolPiece& p : solid.pieces) {
    solid.length = std::max(solid.length, p.h1);
    solid.max_radius = std::max(solid.max_radius, p.maxRadius());
  }
  return solid;
}

namespace {

bool clip(Span& s, const Span& by) {
  s.lo = std::max(s.lo, by.lo);
  s.hi = std::min(s.hi, by.hi);
  return s.lo < s.hi;
}

// Where q(t) = qa t^2 + qb t + qc <= 0 within `range`; `valid` decides between two pieces (the far nappe of a cone).
template <class Valid>
bool quadraticSpan(double qa, double qb, double qc, Span range, Valid valid, Span& out) {
  if (std::abs(qa) < 1e-12) {
    if (std::abs(qb) < 1e-12) {
      if (qc > 0.0) return false;
      out = range;
      return true;
    }
    const double root = -qc / qb;
    Span s = qb > 0.0 ? Span{-1e300, root} : Span{root, 1e300};
    out = s;
    return clip(out, range);
  }
  const double disc = qb * qb - 4.0 * qa * qc;
  if (disc <= 0.0) {
    if (qa > 0.0) return false;
    out = range;
    return true;
  }
  const double root = std::sqrt(disc);
  double t1, t2;
  if (std::abs(qa) > 1e-6) {  // no cancellation worth a division
    const double half = 0.5 / qa;
    t1 = (-qb - root) * half;
    t2 = (-qb + root) * half;
    if (t1 > t2) std::swap(t1, t2);
  } else {
    const double q = -0.5 * (qb + std::copysign(root, qb));
    t1 = std::min(q / qa, qc / q);
    t2 = std::max(q / qa, qc / q);
  }
  if (qa > 0.0) {
    out = {t1, t2};
    return clip(out, range);
  }
  Span below{range.lo, std::min(t1, range.hi)}, above{std::max(t2, range.lo), range.hi};
  const bool has_below = below.lo < below.hi && valid(0.5 * (below.lo + below.hi));
  const bool has_above = above.lo < above.hi && valid(0.5 * (above.lo + above.hi));
  if (!has_below && !has_above) return false;
  out = has_below && has_above ? Span{below.lo, above.hi} : (has_below ? below : above);
  return true;
}

}  // namespace

PieceOnRays::PieceOnRays(const ToolPiece& piece, const ToolPose& pose, int axis) : piece_(&piece) {
  const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
  const Vec3& a = pose.axis;
  au_ = a[u];
  av_ = a[v];
  hd_ = a[axis];
  inv_hd_ = std::abs(hd_) < 1e-12 ? 0.0 : 1.0 / hd_;
  tu_ = pose.tip[u];
  tv_ = pose.tip[v];
  tk_ = pose.tip[axis];
  wk_ = -tk_;  // the ray's origin relative to the tip, along the family's axis
  slope_ = piece.h1 > piece.h0 ? (piece.r1 - piece.r0) / (piece.h1 - piece.h0) : 0.0;
  rho1_ = slope_ * hd_;
  qa_ = piece.sphere ? 1.0 : 1.0 - hd_ * hd_ - rho1_ * rho1_;
}

bool PieceOnRays::span(double u, double v, Span& out) const {
  const ToolPiece& p = *piece_;
  const double du = u - tu_, dv = v - tv_;
  const double hw = au_ * du + av_ * dv + hd_ * wk_;  // height above the tip of the ray's origin
  const double w2 = du * du + dv * dv + tk_ * tk_;
  Span slab;
  if (inv_hd_ == 0.0) {
    if (hw < p.h0 || hw > p.h1) return false;
    slab = {-1e300, 1e300};
  } else {
    const double a = (p.h0 - hw) * inv_hd_, b = (p.h1 - hw) * inv_hd_;
    slab = inv_hd_ > 0.0 ? Span{a, b} : Span{b, a};
  }
  if (p.sphere) {
    const double ck = wk_ - p.centre_h * hd_;
    const double c2 = w2 - 2.0 * p.centre_h * hw + p.centre_h * p.centre_h;
    return quadraticSpan(1.0, 2.0 * ck, c2 - p.sphere_radius * p.sphere_radius, slab, [](double) { return true; }, out);
  }
  // Squared distance from the axis: A t^2 + B t + C; the outline radius along the ray: rho0 + rho1 t.
  const double B = 2.0 * (wk_ - hw * hd_), C = w2 - hw * hw;
  const double rho0 = p.r0 + slope_ * (hw - p.h0), rho1 = rho1_;
  auto valid = [rho0, rho1](double t) { return rho0 + rho1 * t >= 0.0; };
  return quadraticSpan(qa_, B - 2.0 * rho0 * rho1, C - rho0 * rho0, slab, valid, out);
}

bool rayPieceSpan(const ToolPiece& piece, const ToolPose& pose, const Vec3& origin, int axis, Span& out) {
  return PieceOnRays(piece, pose, axis).span(origin[DexelLattice::uAxis(axis)], origin[DexelLattice::vAxis(axis)], out);
}

ToolPiece risePiece(const ToolPiece& piece, double rise) {
  const double r = piece.radiusAt(piece.h1);
  return frustum(piece.zone, piece.h1, piece.h1 + rise, r, r);
}

double penetrationDepth(const ToolPiece& piece, const ToolPose& pose, const Vec3& point) {
  const Vec3 w = point - pose.tip;
  const double h = w.dot(pose.axis);
  const double axial = std::min(h - piece.h0, piece.h1 - h);
  if (axial <= 0.0) return 0.0;
  double radial;
  if (piece.sphere) {
    radial = piece.sphere_radius - (w - piece.centre_h * pose.axis).norm();
  } else {
    const double r = (w - h * pose.axis).norm();
    const double slope = piece.h1 > piece.h0 ? (piece.r1 - piece.r0) / (piece.h1 - piece.h0) : 0.0;
    radial = (piece.radiusAt(h) - r) / std::sqrt(1.0 + slope * slope);
  }
  return std::max(0.0, std::min(axial, radial));
}

double deepestOnSpan(const ToolPiece& piece, const ToolPose& pose, const Vec3& origin, int axis, Span segment,
                     Vec3* where) {
  const Vec3 w = origin - pose.tip;
  const double hd = pose.axis[axis], A = 1.0 - hd * hd;
  double samples[4] = {segment.lo, segment.hi, 0.5 * (segment.lo + segment.hi), 0.5 * (segment.lo + segment.hi)};
  if (A > 1e-12) samples[3] = std::clamp(-(w[axis] - w.dot(pose.axis) * hd) / A, segment.lo, segment.hi);
  double best = -1.0;
  for (double t : samples) {
    Vec3 p = origin;
    p[axis] = t;
    const double d = penetrationDepth(piece, pose, p);
    if (d > best) {
      best = d;
      if (where) *where = p;
    }
  }
  return best;
}

Box pieceBox(const ToolPiece& piece, const ToolPose& pose) {
  Box box;
  const Vec3& a = pose.axis;
  const Vec3 extent = (Vec3::Ones() - a.cwiseProduct(a)).cwiseMax(0.0).cwiseSqrt();
  const double r = piece.maxRadius();
  for (double h : {piece.h0, piece.h1}) {
    const Vec3 c = pose.tip + h * a;
    box.extend(c - r * extent);
    box.extend(c + r * extent);
  }
  return box;
}

}  // namespace art2part
