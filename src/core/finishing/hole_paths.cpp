// What the holes' methods make of them: the plugs roughing treats as part, the drilling runs the post turns into
// canned cycles, the helices of helical milling.
#include <algorithm>
#include <cmath>

#include "hole_internal.h"

namespace art2part {

using namespace hole_detail;

namespace {

constexpr double kPlugChord = 0.01;  // mm: a plug's chords lie inside its bore's circle by at most this
constexpr int kPlugMinSides = 24;
constexpr int kHelixMinSides = 12;

int sidesFor(double radius, double chord, int least) {
  if (radius <= chord) return least;
  return std::max(least, static_cast<int>(std::ceil(kPi / std::acos(1 - chord / radius))));
}

// A closed prism of `sides` round the axis from depth `top` to `bottom` below the mouth, its bottom a cap or a cone to
// `apex` (> bottom), outward.
void addPlug(Mesh& mesh, const Hole& hole, double top, double bottom, double apex) {
  const double radius = 0.5 * hole.diameter;
  const int n = sidesFor(radius, kPlugChord, kPlugMinSides);
  Vec3 u, v;
  orthonormalPair(hole.axis, u, v);  // u x v = axis: angles grow counter-clockwise seen from above
  const int first = static_cast<int>(mesh.vertices.size());
  const Vec3 upper = hole.mouth - top * hole.axis, lower = hole.mouth - bottom * hole.axis;
  for (int k = 0; k < n; ++k) {
    const double angle = 2 * kPi * k / n;
    const Vec3 out = radius * (std::cos(angle) * u + std::sin(angle) * v);
    mesh.vertices.push_back(upper + out);
    mesh.vertices.push_back(lower + out);
  }
  const int top_centre = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(upper);
  mesh.vertices.push_back(apex > bottom ? Vec3(hole.mouth - apex * hole.axis) : lower);
  const int bottom_centre = top_centre + 1;
  for (int k = 0; k < n; ++k) {
    const int p = first + 2 * k, q = first + 2 * ((k + 1) % n);  // upper ring p, q; lower ring p + 1, q + 1
    mesh.triangles.push_back({top_centre, p, q});
    mesh.triangles.push_back({p + 1, q + 1, q});
    mesh.triangles.push_back({p + 1, q, p});
    mesh.triangles.push_back({bottom_centre, q + 1, p + 1});
  }
}

void push(Toolpath& path, CutterLocation point) {
  if (!path.empty() && path.back().move == point.move && (path.back().tip - point.tip).norm() < 1e-9) return;
  path.push_back(std::move(point));
}

// The clearance level along the axis: `clearance_above` over the highest mouth, never under the R planes nor under the
// part's material measured round any of the holes (free_radius) with holder_margin to spare.
double clearanceLevel(const std::vector<Hole>& holes, const Vec3& axis, double clearance_above,
                      const HoleOptions& options) {
  double top = -kInfinity, material = -kInfinity;
  for (const Hole& hole : holes) {
    const double mouth = hole.mouth.dot(axis);
    top = std::max(top, mouth);
    for (size_t k = hole.free_radius.size(); k-- > 0;)
      if (std::isfinite(hole.free_radius[k])) {
        material = std::max(material, mouth + (k + 1) * hole.clearance_step);
        break;
      }
  }
  return std::max(top + std::max(clearance_above, options.retract_height), material + options.holder_margin);
}

// The one axis of a run of holes; throws InputError when one differs from the first's.
Vec3 runAxis(const std::vector<Hole>& holes, const std::string& what, const HoleOptions& options) {
  const Vec3 axis = holes.front().axis.normalized();
  for (size_t h = 1; h < holes.size(); ++h)
    if (axis.cross(holes[h].axis.normalized()).norm() > std::sin(options.axis_tolerance_deg * kDegree) ||
        axis.dot(holes[h].axis) < 0)
      throw InputError(what + ": hole " + std::to_string(h) + " has another axis than hole 0 (one setup "
                       "direction per drilling run)");
  return axis;
}

// Where the R plane of a hole lies.
enum class RPlane {
  OverMouth,  // retract_height over the mouth
  OverBore,   // retract_height over where the main bore begins, where `link` proves the tool may stand there
};

// The R plane of `hole`: retract_height over its mouth; with RPlane::OverBore, for a hole with a counterbore or a
// countersink (bore_start > 0), retract_height over the bore's start instead where the link proves the whole tool
// clear there (over the stock roughing left: the counterbore was cut before the drill comes); a drill fed from over
// the mouth fed through the counterbore's air. Nothing between: over stock the link does not prove cut down to the
// bore, the R plane keeps its retract_height over the mouth.
Vec3 rPlane(const Hole& hole, const Vec3& axis, RPlane where, const HoleLink& link, const HoleOptions& options) {
  const Vec3 over_mouth = hole.mouth + options.retract_height * axis;
  if (where == RPlane::OverMouth || !(hole.bore_start > 0)) return over_mouth;
  const Vec3 over_bore = over_mouth - hole.bore_start * axis;
  const double low = over_bore.dot(axis);
  return link(over_bore, over_bore, low, over_mouth.dot(axis)) <= low ? over_bore : over_mouth;
}

// One run of holes along `axis`: from `level` over the first hole down to its R plane (rPlane), `visit` (its moves
// from the R plane back to it), then to each next hole up to the height `link` gives (never under either R plane nor
// over `level`), across and down to its R plane; back up to `level` at the end.
template <class Visit>
void holeRun(const std::vector<Hole>& holes, const Vec3& axis, double level, const HoleLink& link, RPlane where,
             int setup, const std::string& tool, const HoleOptions& options, Toolpath& path, Visit visit) {
  const auto over = [&](const Hole& hole, double height) {
    return Vec3(hole.mouth + (height - hole.mouth.dot(axis)) * axis);
  };
  const auto rapid = [&](const Vec3& to) { push(path, cutterLocation(setup, tool, MoveKind::Rapid, to, axis)); };
  Vec3 before = Vec3::Zero();  // the R plane of the hole before
  for (std::size_t h = 0; h < holes.size(); ++h) {
    const Vec3 r_plane = rPlane(holes[h], axis, where, link, options);
    if (h == 0) {
      rapid(over(holes[h], level));
    } else {
      const double lowest = std::max(before.dot(axis), r_plane.dot(axis));
      const double height = std::clamp(link(before, r_plane, lowest, level), lowest, std::max(lowest, level));
      rapid(over(holes[h - 1], height));
      rapid(over(holes[h], height));
    }
    rapid(r_plane);
    visit(holes[h], r_plane);
    before = r_plane;
  }
  rapid(over(holes.back(), level));
}

// A helix from the R plane: out to radius (bore - tool) / 2, down helix_pitch_ratio x D per turn (counter-clockwise
// seen from the spindle: climb milling inside a bore), one turn at the floor, back to the centre and up to the R plane.
void helixDown(const Hole& hole, const Tool& tool, int setup, const Vec3& axis, const Vec3& r_plane,
               const HoleOptions& options, Toolpath& path) {
  Vec3 u, v;
  orthonormalPair(axis, u, v);
  const double offset = 0.5 * (hole.diameter - tool.diameter), depth = helixDepth(hole, options);
  const double pitch = options.helix_pitch_ratio * tool.diameter;
  const int sides = sidesFor(offset, options.helix_chord, kHelixMinSides);
  const auto at = [&](double angle, double below_r_plane) {
    return Vec3(r_plane - below_r_plane * axis + offset * (std::cos(angle) * u + std::sin(angle) * v));
  };
  const auto feed = [&](const Vec3& to) { push(path, cutterLocation(setup, tool.id, MoveKind::Feed, to, axis)); };
  feed(at(0, 0));
  const double drop = options.retract_height + depth;
  const int steps = std::max(1, static_cast<int>(std::ceil(drop / pitch * sides)));
  for (int j = 1; j <= steps; ++j) feed(at(2 * kPi * j / sides, drop * j / steps));
  const double end_angle = 2 * kPi * steps / sides;
  for (int j = 1; j <= sides; ++j) feed(at(end_angle + 2 * kPi * j / sides, drop));
  feed(hole.mouth - depth * axis);
  push(path, cutterLocation(setup, tool.id, MoveKind::Rapid, r_plane, axis));
}

}  // namespace

double linkAtClearanceLevel(const Vec3&, const Vec3&, double, double level) { return level; }

Mesh holePlugs(const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods) {
  if (holes.size() != methods.size())
    throw InputError("holePlugs: " + std::to_string(holes.size()) + " holes but " + std::to_string(methods.size()) +
                     " methods");
  Mesh mesh;
  for (size_t h = 0; h < holes.size(); ++h) {
    const Hole& hole = holes[h];
    if (methods[h].method == HoleMethod::None || !(hole.diameter > 0)) continue;
    switch (hole.bottom) {
      case HoleBottom::Cone: addPlug(mesh, hole, hole.bore_start, hole.depth, hole.total_depth); break;
      case HoleBottom::Through: addPlug(mesh, hole, hole.bore_start, hole.total_depth, 0); break;
      default: addPlug(mesh, hole, hole.bore_start, hole.depth, 0); break;
    }
  }
  return mesh;
}

Toolpath drillingPath(const std::vector<Hole>& holes, const Tool& tool, bool spot, int setup, double clearance_above,
                      const HoleOptions& options, const HoleLink& link) {
  if (tool.type != ToolType::Drill) throw InputError("drillingPath: tool '" + tool.id + "' is not a drill");
  Toolpath path;
  if (holes.empty()) return path;
  const Vec3 axis = runAxis(holes, "drillingPath", options);
  const double level = clearanceLevel(holes, axis, clearance_above, options);
  holeRun(holes, axis, level, link, RPlane::OverBore, setup, tool.id, options, path,
          [&](const Hole& hole, const Vec3& r_plane) {
    const double depth = spot ? spotDepth(hole, tool, options) : drillDepth(hole, tool, options);
    push(path, cutterLocation(setup, tool.id, MoveKind::Feed, hole.mouth - depth * axis, axis));
    push(path, cutterLocation(setup, tool.id, MoveKind::Rapid, r_plane, axis));
  });
  return path;
}

Toolpath helixPath(const Hole& hole, const Tool& tool, int setup, double clearance_above, const HoleOptions& options) {
  return helixPaths({hole}, tool, setup, clearance_above, options);
}

Toolpath helixPaths(const std::vector<Hole>& holes, const Tool& tool, int setup, double clearance_above,
                    const HoleOptions& options, const HoleLink& link) {
  for (const Hole& hole : holes)
    if (tool.type != ToolType::Flat || !(tool.diameter < hole.diameter))
      throw InputError("helixPath: tool '" + tool.id + "' is not a flat end mill narrower than the " +
                       std::to_string(hole.diameter) + " mm hole");
  if (!(options.helix_pitch_ratio > 0) || !(options.helix_chord > 0))
    throw InputError("helixPath: helix_pitch_ratio and helix_chord must be positive");
  Toolpath path;
  if (holes.empty()) return path;
  const Vec3 axis = runAxis(holes, "helixPaths", options);
  const double level = clearanceLevel(holes, axis, clearance_above, options);
  holeRun(holes, axis, level, link, RPlane::OverMouth, setup, tool.id, options, path,
          [&](const Hole& hole, const Vec3& r_plane) {
    helixDown(hole, tool, setup, axis, r_plane, options, path);
  });
  return path;
}

}  // namespace art2part
