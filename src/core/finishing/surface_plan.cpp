// Planning the passes of one direction: the CL map over the faces, the region and its steep and shallow parts, the
// clearance maps, the stepovers, raster and waterline passes, and what the planner believes they reach.
#include "surface_plan.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "art2part/finishing/finishing.h"
#include "art2part/roughing/shadow.h"

namespace art2part::surface {

namespace {

// Triangles whose outward normal points below the direction by more than this (n.z) face away from the tool.
constexpr double kFacingTolerance = 1e-6;
// mm: a face triangle counts as reached when the tool can come this close to its centroid: the tolerance of the
// coverage figure (surface_coverage.h).
constexpr double kReachTolerance = 0.05;
// mm: the CL point of a wall's point is taken this far off the wall; exactly at the tool's radius the tool stands on
// the cliff's edge and touches the wall's top instead.
constexpr double kOffWall = 1e-4;
// A flat end mill on a level face leaves no cusp: its passes overlap by a fifth of the diameter.
constexpr double kFlatStepoverOfDiameter = 0.8;
// The body's clearance maps are this much coarser than the CL map (their radii grow by their pitch).
constexpr double kClearancePitchFactor = 2;
// The CL map's nodes at most (about 40 bytes each).
constexpr double kMaxMapNodes = 16e6;

Vec3 unitNormal(const std::vector<Vec3>& v, const Triangle& t) {
  const Vec3 n = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]);
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

// Distance in x-y from (x, y) to the triangle q (2-D).
double distanceToTriangle(const double q[3][2], double x, double y) {
  double s[3];
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    s[k] = (q[l][0] - q[k][0]) * (y - q[k][1]) - (q[l][1] - q[k][1]) * (x - q[k][0]);
  }
  if ((s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0)) return 0;
  double best = kInf;
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    const double ex = q[l][0] - q[k][0], ey = q[l][1] - q[k][1];
    const double len2 = ex * ex + ey * ey;
    const double t = len2 > 0 ? std::clamp(((x - q[k][0]) * ex + (y - q[k][1]) * ey) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(x - q[k][0] - t * ex, y - q[k][1] - t * ey));
  }
  return best;
}

// Concave bends of the CL surface tighter than this (times the tool's effective radius) are creases, where the tool
// touches two sides of a hollow it does not fit: what is left there is rest finishing's, not a scallop. Above it a
// smooth hollow of radius P > 1.5 R takes at least 0.58 times the flat's spacing; below, the cusp may grow up to
// P / (P - R) times the target, on hollows no wider than the tool.
constexpr double kCreaseOfRadius = 0.5;
// Concave bends wider than this (times the tool's effective radius) count as flat: the spacing they ask for is within
// 0.1 % of the flat's.
constexpr double kFlatOfRadius = 1000;
// A mesh's concave creases never take the spacing below this share of the smooth surface's (see `crease`).
constexpr double kMinCreaseShare = 0.5;
// Concave radii below the tool's (times this) are hollows the tool cannot follow.
constexpr double kFollowableConcave = 1.001;
// Second derivatives of the CL map span this many nodes each way: a mesh's facets make the CL surface a chain of
// slight creases, which one node each way reads as bends tighter than the surface's.
constexpr int kBendStencil = 2;

struct Derivatives {
  double x = 0, y = 0, xx = 0, yy = 0, xy = 0;
};

// First derivatives by central (or one-sided) differences, second ones over kBendStencil nodes (0 where the stencil
// leaves the nodes the tool touches the part at).
Derivatives derivatives(const Context& ctx, int i, int j) {
  const Grid& g = ctx.grid;
  auto usable = [&](int a, int b) { return a >= 0 && b >= 0 && a < g.nx && b < g.ny && ctx.contact[g.node(a, b)] >= 0; };
  auto h = [&](int a, int b) { return ctx.height[g.node(a, b)]; };
  auto first = [&](int di, int dj) {
    const bool fwd = usable(i + di, j + dj), back = usable(i - di, j - dj);
    if (!fwd && !back) return 0.0;
    const double zf = fwd ? h(i + di, j + dj) : h(i, j), zb = back ? h(i - di, j - dj) : h(i, j);
    return (zf - zb) / ((fwd + back) * g.pitch);
  };
  const int k = kBendStencil;
  const double step2 = (k * g.pitch) * (k * g.pitch);
  auto second = [&](int di, int dj) {
    if (!usable(i + k * di, j + k * dj) || !usable(i - k * di, j - k * dj)) return 0.0;
    return (h(i + k * di, j + k * dj) - 2 * h(i, j) + h(i - k * di, j - k * dj)) / step2;
  };
  Derivatives d;
  d.x = first(1, 0);
  d.y = first(0, 1);
  d.xx = second(1, 0);
  d.yy = second(0, 1);
  if (usable(i + k, j + k) && usable(i + k, j - k) && usable(i - k, j + k) && usable(i - k, j - k))
    d.xy = (h(i + k, j + k) - h(i + k, j - k) - h(i - k, j + k) + h(i - k, j - k)) / (4 * step2);
  return d;
}

// The region grown by `cells` nodes (a square), onto nodes the tool touches the part at.
void dilate(const Context& ctx, std::vector<std::uint8_t>& mask, int cells) {
  const Grid& g = ctx.grid;
  auto usable = [&](int n) { return ctx.contact[n] >= 0; };
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint8_t> out(mask.size(), 0);
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        if (!mask[g.node(i, j)]) continue;
        for (int d = -cells; d <= cells; ++d) {
          const int ii = pass == 0 ? i + d : i, jj = pass == 0 ? j : j + d;
          if (ii < 0 || jj < 0 || ii >= g.nx || jj >= g.ny) continue;
          if (usable(g.node(ii, jj))) out[g.node(ii, jj)] = 1;
        }
      }
    mask.swap(out);
  }
}

// The x-y offset from a point of a triangle (unit normal n, facing the tool) to the tool's centre when the tool
// touches the triangle there: R' along the normal's horizontal direction and r along the normal (just off a wall).
Eigen::Vector2d contactOffset(const Vec3& n, double Rp, double r) {
  const double nxy = std::hypot(n.x(), n.y());
  const double ux = nxy > 1e-12 ? n.x() / nxy : 0, uy = nxy > 1e-12 ? n.y() / nxy : 0;
  return Eigen::Vector2d((Rp + kOffWall) * ux + r * n.x(), (Rp + kOffWall) * uy + r * n.y());
}

// The CL map at the nodes within `grow` of a facing face triangle's box (NaN and no contact elsewhere).
void computeHeights(Context& ctx, const std::vector<Vec3>& v, const std::vector<Triangle>& tris,
                    const std::vector<int>& facing, double grow) {
  const Grid& g = ctx.grid;
  std::vector<char> candidate(g.size(), 0);
  for (int t : facing) {
    double lo[2] = {kInf, kInf}, hi[2] = {-kInf, -kInf};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], v[tris[t][k]][a]), hi[a] = std::max(hi[a], v[tris[t][k]][a]);
    for (int j = g.nearestJ(lo[1] - grow); j <= g.nearestJ(hi[1] + grow); ++j)
      for (int i = g.nearestI(lo[0] - grow); i <= g.nearestI(hi[0] + grow); ++i) candidate[g.node(i, j)] = 1;
  }
  ctx.height.assign(g.size(), std::nan(""));
  ctx.contact.assign(g.size(), -1);
  parallelFor(g.ny, ctx.threads, [&](int j) {
    long count = 0;
    for (int i = 0; i < g.nx; ++i) {
      const int n = g.node(i, j);
      if (!candidate[n]) continue;
      int triangle;
      ctx.height[n] = ctx.cutter->drop(g.x(i), g.y(j), ctx.floor, &triangle);
      ctx.contact[n] = triangle;
      ++count;
    }
    ctx.drops.fetch_add(count, std::memory_order_relaxed);
  });
}

// The region: nodes touching a face triangle, and the nodes where a face triangle's facet contact lies (the triangle
// shifted by the tool's contact offset) unless something higher holds the tool there; grown by the margin.
void markRegion(Context& ctx, const std::vector<Vec3>& v, const std::vector<Triangle>& tris,
                const std::vector<int>& facing, const std::vector<char>& in_face, double Rp, double r, double margin) {
  const Grid& g = ctx.grid;
  ctx.region.assign(g.size(), 0);
  for (std::size_t n = 0; n < g.size(); ++n) ctx.region[n] = ctx.contact[n] >= 0 && in_face[ctx.contact[n]];
  const double near = 0.7072 * g.pitch;  // every point lies within this of its nearest node
  for (int t : facing) {
    const Eigen::Vector2d off = contactOffset(unitNormal(v, tris[t]), Rp, r);
    double q[3][2], zmax = -kInf, lo[2] = {kInf, kInf}, hi[2] = {-kInf, -kInf};
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = v[tris[t][k]];
      q[k][0] = p.x() + off.x();
      q[k][1] = p.y() + off.y();
      zmax = std::max(zmax, p.z());
      for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], q[k][a]), hi[a] = std::max(hi[a], q[k][a]);
    }
    for (int j = g.nearestJ(lo[1] - near); j <= g.nearestJ(hi[1] + near); ++j)
      for (int i = g.nearestI(lo[0] - near); i <= g.nearestI(hi[0] + near); ++i) {
        const int n = g.node(i, j);
        if (ctx.region[n] || ctx.contact[n] < 0 || ctx.height[n] > zmax + kReachTolerance) continue;
        if (distanceToTriangle(q, g.x(i), g.y(j)) <= near) ctx.region[n] = 1;
      }
  }
  dilate(ctx, ctx.region, static_cast<int>(std::ceil(margin / g.pitch)));
}

// The spacing each node of the region asks for, from the scallop, the slope and the concave radius under it.
struct Spacings {
  const Part& part;
  const std::vector<Vec3>& v;      // the part's vertices in the frame
  std::vector<double> face_radius; // faceConcaveRadii
  double R = 0, r = 0;             // the cutting radius and the effective (corner) radius
  double flat = 0;                 // the centre spacing on a flat
  double row_scallop = 0, level_scallop = 0;  // the scallop less what chords may leave

  // The concave part radius under the node's contact along a section bending by `bend` (a second derivative of the
  // CL map) at `slope`: the face's B-rep radius where it has one, else 1 / curvature + r unless that is a crease (the
  // tool against two sides of a hollow it does not fit) or as good as flat; infinity for convex and flat.
  double concave(int contact, double bend, double slope) const {
    const double fr = face_radius[part.triangle_face[contact]];
    if (fr > kFollowableConcave * r && !std::isinf(fr)) return fr;
    const double kappa = bend / std::pow(1 + slope * slope, 1.5);
    if (!(kappa > 0) || r <= 0) return kInf;
    const double centre = 1 / kappa;
    return centre >= kCreaseOfRadius * r && centre < kFlatOfRadius * r ? centre + r : kInf;
  }

  double centreSpacing(double radius, double scallop) const {
    const bool concave = radius > kFollowableConcave * r && !std::isinf(radius);
    return r > 0 ? scallopStepover(r, scallop, concave ? -radius : kInf) : flat;
  }

  // The mesh's own concave creases under the tool (a tessellation's facets, a mesh part's triangles): the contact
  // triangle's concave edges, each bending the section across the passes, which run along (dx, dy), by its dihedral
  // angle times how far the edge runs along them. Only edges the adjacency calls smooth count: sharper ones are
  // features of the part (a fillet's or a corner's), where what the tool leaves is rest finishing's.
  double crease(int t, double dx, double dy) const {
    if (part.adjacency.dihedral.size() != part.mesh.triangles.size()) return 0;
    double worst = 0;
    for (int e = 0; e < 3; ++e) {
      const double angle = part.adjacency.dihedral[t][e];
      if (angle >= 0 || part.adjacency.klass[t][e] != EdgeClass::Smooth) continue;
      const Triangle& tri = part.mesh.triangles[t];
      const Vec3 dir = (v[tri[(e + 1) % 3]] - v[tri[e]]).normalized();
      worst = std::max(worst, -angle * std::abs(dir.x() * dx + dir.y() * dy));
    }
    return worst;
  }

  // A crease of angle theta midway between two passes raises their cusp by c theta / 4 + r theta^2 / 8 (the two balls
  // sit on planes meeting at it): the spacing c solves c^2 P / (8 r (P - r)) + c theta / 4 + r theta^2 / 8 = h to
  // first order, never below kMinCreaseShare of the smooth spacing.
  double withCreases(double smooth, double radius, double theta, double scallop) const {
    if (!(theta > 0)) return smooth;
    const double A = std::isinf(radius) ? 1 / (8 * r) : radius / (8 * r * (radius - r));
    const double B = 0.25 * theta, C = 0.125 * r * theta * theta - scallop;
    const double c = C < 0 ? (-B + std::sqrt(B * B - 4 * A * C)) / (2 * A) : 0;
    return std::clamp(c, kMinCreaseShare * smooth, smooth);
  }

  // Raster rows run along x: the section across them is along y. Slope alpha across them spreads them on the surface
  // by 1 / cos alpha. A flat end mill's staircase: h = s sin(alpha).
  double row(int contact, const Derivatives& d, double& radius) const {
    const double across = std::abs(d.y);
    if (r <= 0) {
      const double sin_a = std::sin(std::atan(across));
      return sin_a > 0 ? std::min(flat, row_scallop / sin_a) : flat;
    }
    radius = concave(contact, d.yy, across);
    return withCreases(centreSpacing(radius, row_scallop), radius, crease(contact, 1, 0), row_scallop) *
           std::cos(std::atan(across));
  }

  // Waterline levels: the section up the slope (the gradient); levels a centre spacing apart on a slope alpha are
  // that times sin alpha apart in height. A flat end mill's staircase: h = dz cos(alpha).
  double level(int contact, const Derivatives& d, double& radius) const {
    const double up = std::hypot(d.x, d.y);
    if (r <= 0) return std::min(R, level_scallop / std::cos(std::atan(up)));
    const double gx = d.x / up, gy = d.y / up;
    radius = concave(contact, gx * gx * d.xx + 2 * gx * gy * d.xy + gy * gy * d.yy, up);
    return withCreases(centreSpacing(radius, level_scallop), radius, crease(contact, -gy, gx), level_scallop) *
           std::sin(std::atan(up));
  }
};

// Slopes of the CL surface; the steep and shallow parts, overlapping by kSteepOverlapDeg each way; each node's
// spacing. Nodes where the shank or holder cannot clear are left out of both parts: no passes are planned over them.
// Returns the least concave radius that set a spacing (infinity: none).
double splitRegion(Context& ctx, const Spacings& spacings, double steep_angle_deg) {
  const Grid& g = ctx.grid;
  ctx.slope.assign(g.size(), 0);
  ctx.raster.assign(g.size(), 0);
  ctx.waterline.assign(g.size(), 0);
  ctx.row_spacing.assign(g.size(), kInf);
  ctx.level_spacing.assign(g.size(), kInf);
  const double tan_shallow = std::tan((steep_angle_deg + kSteepOverlapDeg) * M_PI / 180);
  const double tan_steep = std::tan((steep_angle_deg - kSteepOverlapDeg) * M_PI / 180);
  double least = kInf;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const int n = g.node(i, j);
      if (!ctx.region[n] || !ctx.bodyClear(Vec3(g.x(i), g.y(j), ctx.height[n]))) continue;
      const Derivatives d = derivatives(ctx, i, j);
      ctx.slope[n] = std::hypot(d.x, d.y);
      ctx.raster[n] = ctx.slope[n] < tan_shallow;
      ctx.waterline[n] = ctx.slope[n] > tan_steep;
      double radius = kInf;
      if (ctx.raster[n]) ctx.row_spacing[n] = spacings.row(ctx.contact[n], d, radius), least = std::min(least, radius);
      if (ctx.waterline[n])
        ctx.level_spacing[n] = spacings.level(ctx.contact[n], d, radius), least = std::min(least, radius);
    }
  return least;
}

// What the planner believes: a facing face triangle is reached when the tool can come to its centroid (its CL point
// there is no higher than the contact) within the region, and cut when the body clears there too.
void believedAreas(const Context& ctx, const Part& part, const std::vector<Vec3>& v, const std::vector<int>& facing,
                   double Rp, double r, Plan& plan, SurfaceFinishingResult& result) {
  for (int t : facing) {
    const Triangle& tri = part.mesh.triangles[t];
    const double area = triangleArea(part.mesh, t);
    const Vec3 nrm = unitNormal(v, tri);
    const Vec3 c = (v[tri[0]] + v[tri[1]] + v[tri[2]]) / 3;
    const Eigen::Vector2d q = c.head<2>() + contactOffset(nrm, Rp, r);
    const double expected = c.z() - r + r * nrm.z();
    const double z = ctx.drop(q.x(), q.y());
    if (z > expected + kReachTolerance || !ctx.inRegion(q.x(), q.y()))
      result.unreached_area_mm2 += area;
    else if (!ctx.bodyClear(Vec3(q.x(), q.y(), z)))
      result.skipped_area_mm2 += area;
    else
      result.planned_area_mm2 += area, plan.planned.push_back(t);
  }
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

Plan planPasses(const Part& part, const std::vector<int>& faces_in, const SetupFrame& frame, const Tool& tool,
                const SurfaceFinishingOptions& o, bool body, const std::vector<SlabState>& stock_beyond,
                SurfaceFinishingResult& result) {
  const auto start = std::chrono::steady_clock::now();
  checkTool(tool);
  if (tool.type == ToolType::Drill)
    throw InputError("surface finishing: tool '" + tool.id + "' is a drill (ball, bull or flat end mills only)");
  checkOptions(o);
  Plan plan;
  plan.faces = checkedFaces(part, faces_in);
  plan.vertices = toFrame(part.mesh.vertices, frame);
  const std::vector<Vec3>& v = plan.vertices;
  const std::vector<Triangle>& tris = part.mesh.triangles;
  plan.cutter = std::make_unique<DropCutter>(v, tris, tool);
  const double R = 0.5 * tool.diameter, r = plan.cutter->cornerRadius(), Rp = R - r;
  const Box bounds = plan.cutter->bounds();
  plan.top = bounds.max.z();
  plan.short_link = o.short_link_mm > 0 ? o.short_link_mm : kInf;

  // The spacing of the cutter centres on a flat (a flat end mill: passes overlapping by a fifth).
  const double spacing = r > 0 ? scallopStepover(r, o.scallop, kInf) : kFlatStepoverOfDiameter * tool.diameter;
  result.stepover_mm = spacing;
  double pitch = o.map_pitch > 0 ? o.map_pitch : 0.25 * R;

  // The faces' triangles, and those facing the direction (the window of the map).
  std::vector<char> face_member(part.faces.size(), 0), in_face(tris.size(), 0);
  for (int f : plan.faces) face_member[f] = 1;
  std::vector<int> facing;
  Box window;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    if (!face_member[part.triangle_face[t]]) continue;
    in_face[t] = 1;
    if (unitNormal(v, tris[t]).z() < -kFacingTolerance) {
      result.unreached_area_mm2 += triangleArea(part.mesh, static_cast<int>(t));
      continue;
    }
    facing.push_back(static_cast<int>(t));
    for (int k = 0; k < 3; ++k) window.extend(v[tris[t][k]]);
  }
  if (facing.empty()) {
    result.seconds_map = secondsSince(start);
    return plan;
  }
  // A small tool over a large part: the map keeps to kMaxMapNodes by a coarser pitch (the passes' points are drops
  // and refined all the same; only the region's edges and the contours' first crossings come coarser).
  const Vec3 extent = window.size() + Vec3::Constant(2 * (R + spacing) + 4 * pitch);
  pitch = std::max(pitch, std::sqrt(extent.x() * extent.y() / kMaxMapNodes));
  const double margin = std::max(o.region_margin > 0 ? o.region_margin : spacing, pitch);
  const double reach = R + margin + 2 * pitch;
  window.min -= Vec3(reach, reach, 0);
  window.max += Vec3(reach, reach, 0);

  plan.ctx = std::make_unique<Context>();
  Context& ctx = *plan.ctx;
  ctx.cutter = plan.cutter.get();
  ctx.floor = bounds.min.z() - 2 * R - 1;
  ctx.grid = gridOver(window, pitch);
  // What chords may leave above the CL surface comes out of the scallop: never more than a third of it each.
  ctx.gouge_tolerance = 0.5 * o.chordal_tolerance;
  ctx.leave_tolerance = std::min(kRasterLeaveShare * o.chordal_tolerance, o.scallop / 3);
  ctx.contour_leave = std::min(kContourLeaveShare * o.chordal_tolerance, o.scallop / 3);
  ctx.crossing_precision = std::min(kCrossingShare * o.chordal_tolerance, o.scallop / 12);
  ctx.sample_step = o.sample_step > 0 ? o.sample_step : 0.1 * R;
  ctx.min_step = 0.25 * o.chordal_tolerance;
  ctx.feed_link = o.feed_link_mm > 0 ? o.feed_link_mm : tool.diameter;
  ctx.contours_both_ways = o.waterline_both_ways;
  ctx.threads = threadCount(o.threads);

  computeHeights(ctx, v, tris, facing, R + margin + pitch);
  markRegion(ctx, v, tris, facing, in_face, Rp, r, margin);
  if (body) {  // the body's clearance maps
    const Grid coarse = gridOver(window, kClearancePitchFactor * pitch);
    ctx.body = clearanceMap(v, tris, coarse, bodyZones(tool, o.skin + o.holder_margin), ctx.threads, ctx.drops);
    ctx.safe = clearanceMap(v, tris, coarse, {Zone{R, 0, o.skin}}, ctx.threads, ctx.drops);
    raiseOverStock(ctx.body, stock_beyond, bodyZones(tool, o.holder_margin));
    raiseOverStock(ctx.safe, stock_beyond, {Zone{R, 0, 0}});
    for (std::size_t n = 0; n < ctx.safe.tip.size(); ++n) ctx.safe.tip[n] = std::max(ctx.safe.tip[n], ctx.body.tip[n]);
  }
  const Spacings spacings{part, v, faceConcaveRadii(part), R, r, spacing, o.scallop - ctx.leave_tolerance,
                          o.scallop - ctx.contour_leave - ctx.crossing_precision};
  const double least = splitRegion(ctx, spacings, o.steep_angle_deg);
  result.least_radius_mm = std::isinf(least) ? kInf : -least;
  plan.clearance_z = plan.top + o.clearance;
  for (double z : ctx.safe.tip) plan.clearance_z = std::max(plan.clearance_z, z + o.link_margin);
  result.seconds_map = secondsSince(start);

  auto clock = std::chrono::steady_clock::now();
  const auto rows = rasterRows(ctx, result.raster_stepover_mm);
  result.seconds_raster = secondsSince(clock);
  clock = std::chrono::steady_clock::now();
  const auto levels = waterlineLevels(ctx, result.height_step_mm);
  result.seconds_waterline = secondsSince(clock);
  plan.ordered = orderPasses(ctx, levels, rows);
  result.raster_passes = plan.ordered.raster_runs;
  result.waterline_levels = plan.ordered.levels;
  result.waterline_contours = plan.ordered.contours;
  believedAreas(ctx, part, v, facing, Rp, r, plan, result);
  return plan;
}

}  // namespace art2part::surface
