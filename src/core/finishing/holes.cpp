// Hole recognition (holes.h): concave cylinders grown along their axis line through the face adjacency into the run
// of faces that makes one hole, its mouth and bottom found, its segments ordered from the mouth down, the part's
// material around its axis measured in bands.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "hole_internal.h"

namespace art2part {

using namespace hole_detail;

const char* holeSegmentKindName(HoleSegmentKind kind) {
  switch (kind) {
    case HoleSegmentKind::Cylinder: return "cylinder";
    case HoleSegmentKind::Cone: return "cone";
    case HoleSegmentKind::Flat: return "flat";
    case HoleSegmentKind::Torus: return "torus";
    case HoleSegmentKind::Sphere: return "sphere";
  }
  return "cylinder";
}

const char* holeBottomName(HoleBottom bottom) {
  switch (bottom) {
    case HoleBottom::Through: return "through";
    case HoleBottom::Flat: return "flat";
    case HoleBottom::Cone: return "cone";
    case HoleBottom::Other: return "other";
  }
  return "through";
}

namespace {

constexpr int kArcBins = 360;          // a bore's reach round its axis is counted in 1 degree bins
constexpr double kPierceSlack = 1e-7;  // barycentric slack of the axis-through-a-triangle test (the apex of a cone is a
                                       // vertex: the axis passes exactly through it)
constexpr double kApexRatio = 0.05;    // a cone reaching within this x the bore's radius of the axis closes the hole

// Triangles and vertices of each face, and which faces share an edge.
struct FaceIndex {
  std::vector<std::vector<int>> triangles;
  std::vector<std::vector<int>> vertices;
  std::vector<std::set<int>> neighbours;
};

FaceIndex indexFaces(const Part& part) {
  const int faces = static_cast<int>(part.faces.size());
  FaceIndex index;
  index.triangles.resize(faces);
  index.vertices.resize(faces);
  index.neighbours.resize(faces);
  const int triangles = std::min(part.mesh.triangleCount(), static_cast<int>(part.triangle_face.size()));
  for (int t = 0; t < triangles; ++t) {
    const int f = part.triangle_face[t];
    if (f < 0 || f >= faces) continue;
    index.triangles[f].push_back(t);
    for (int v : part.mesh.triangles[t]) index.vertices[f].push_back(v);
    if (t >= static_cast<int>(part.adjacency.neighbour.size())) continue;
    for (int n : part.adjacency.neighbour[t]) {
      if (n < 0 || n >= triangles) continue;
      const int g = part.triangle_face[n];
      if (g != f && g >= 0 && g < faces) index.neighbours[f].insert(g);
    }
  }
  for (std::vector<int>& list : index.vertices) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return index;
}

// The axis line a hole is grown along, with the tolerances its faces must meet.
struct AxisLine {
  Vec3 origin = Vec3::Zero(), axis = Vec3::UnitZ();
  double sin_angle = 0;  // axes parallel within this (sine of the angle)
  double line = 0;       // mm: points on the line, radii equal, within this
};

double lineDistance(const AxisLine& line, const Vec3& p) {
  const Vec3 d = p - line.origin;
  return (d - line.axis * line.axis.dot(d)).norm();
}

bool parallel(const AxisLine& line, const Vec3& direction) {
  const double n = direction.norm();
  return n > 0 && std::isfinite(n) && line.axis.cross(direction / n).norm() <= line.sin_angle;
}

bool validCylinder(const Face& face) {
  return face.type == SurfaceType::Cylinder && face.concave && face.radius > 0 && std::isfinite(face.radius) &&
         face.axis.allFinite() && face.axis.norm() > 0.5 && face.point.allFinite();
}

// A concave surface of revolution on the line: a candidate segment of the hole.
bool coaxialMember(const AxisLine& line, const Face& face) {
  if (!face.concave || !face.point.allFinite()) return false;
  switch (face.type) {
    case SurfaceType::Cylinder:
    case SurfaceType::Cone:
    case SurfaceType::Torus:
      return parallel(line, face.axis) && lineDistance(line, face.point) <= line.line;
    case SurfaceType::Sphere:
      return lineDistance(line, face.point) <= line.line;
    default:
      return false;
  }
}

double radial(const AxisLine& line, const Vec3& p) { return lineDistance(line, p); }
double along(const AxisLine& line, const Vec3& p) { return line.axis.dot(p - line.origin); }

struct Extent {
  double lo = kInfinity, hi = -kInfinity;    // along the line's axis
  double r_min = kInfinity, r_max = -kInfinity;
};

Extent extentOf(const Part& part, const FaceIndex& index, const AxisLine& line, int face) {
  Extent e;
  for (int v : index.vertices[face]) {
    const Vec3& p = part.mesh.vertices[v];
    const double t = along(line, p), r = radial(line, p);
    e.lo = std::min(e.lo, t);
    e.hi = std::max(e.hi, t);
    e.r_min = std::min(e.r_min, r);
    e.r_max = std::max(e.r_max, r);
  }
  return e;
}

// A plane square to the axis belongs to the hole when a coaxial concave neighbour on the side its normal points to
// (the hole's empty side) is at least as wide as the plane: a flat bottom, a counterbore's step. The face the hole
// opens in has the hole on its other side.
bool planeBelongs(const Part& part, const FaceIndex& index, const AxisLine& line, int plane) {
  const Face& face = part.faces[plane];
  if (face.type != SurfaceType::Plane || !parallel(line, face.normal) || index.vertices[plane].empty()) return false;
  const Extent flat = extentOf(part, index, line, plane);
  const double side = face.normal.dot(line.axis) > 0 ? 1.0 : -1.0;
  const double level = 0.5 * (flat.lo + flat.hi);
  for (int g : index.neighbours[plane]) {
    if (!coaxialMember(line, part.faces[g]) || index.vertices[g].empty()) continue;
    const Extent wall = extentOf(part, index, line, g);
    if ((0.5 * (wall.lo + wall.hi) - level) * side <= 0) continue;
    if (flat.r_max <= wall.r_max + line.line) return true;
  }
  return false;
}

// The faces of one hole: the seed's coaxial concave neighbours, and planes that belong, grown to a fixed point.
std::vector<int> growHole(const Part& part, const FaceIndex& index, const AxisLine& line, int seed,
                          const std::vector<char>& taken) {
  std::set<int> members = {seed}, rejected;
  std::vector<int> queue = {seed};
  while (!queue.empty()) {
    const int f = queue.back();
    queue.pop_back();
    for (int g : index.neighbours[f]) {
      if (members.count(g) || rejected.count(g) || taken[g] || index.triangles[g].empty()) continue;
      const bool member = part.faces[g].type == SurfaceType::Plane ? planeBelongs(part, index, line, g)
                                                                   : coaxialMember(line, part.faces[g]);
      if (!member) {
        rejected.insert(g);
        continue;
      }
      members.insert(g);
      queue.push_back(g);
    }
  }
  return std::vector<int>(members.begin(), members.end());
}

// Whether the axis line passes through one of the face's triangles.
bool axisPierces(const Part& part, const FaceIndex& index, const AxisLine& line, int face) {
  for (int t : index.triangles[face]) {
    const Vec3& a = part.mesh.corner(t, 0);
    const Vec3 e1 = part.mesh.corner(t, 1) - a, e2 = part.mesh.corner(t, 2) - a;
    const Vec3 p = line.axis.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14 * std::max(1.0, e1.squaredNorm() * e2.norm())) continue;  // edge-on
    const Vec3 s = line.origin - a;
    const double u = s.dot(p) / det;
    if (u < -kPierceSlack || u > 1 + kPierceSlack) continue;
    const double w = line.axis.dot(s.cross(e1)) / det;
    if (w < -kPierceSlack || u + w > 1 + kPierceSlack) continue;
    return true;
  }
  return false;
}

// How far round the axis the faces' triangles reach, degrees (1 degree bins).
double arcDegrees(const Part& part, const FaceIndex& index, const AxisLine& line, const std::vector<int>& faces) {
  Vec3 u, v;
  orthonormalPair(line.axis, u, v);
  std::array<bool, kArcBins> covered{};
  for (int f : faces)
    for (int t : index.triangles[f]) {
      std::array<double, 3> angle;
      for (int c = 0; c < 3; ++c) {
        const Vec3 d = part.mesh.corner(t, c) - line.origin;
        angle[c] = std::atan2(d.dot(v), d.dot(u)) / kDegree;  // (-180, 180]
      }
      // The shortest arc holding the three angles: from the corner after the widest gap round the circle.
      std::sort(angle.begin(), angle.end());
      double start = angle[0], span = angle[2] - angle[0];
      for (int c = 0; c < 2; ++c) {
        const double other = angle[c] + 360 - angle[c + 1];  // start at corner c + 1, wrap round to corner c
        if (other < span) span = other, start = angle[c + 1];
      }
      const int first = static_cast<int>(std::floor(start)), last = static_cast<int>(std::ceil(start + span));
      for (int b = first; b < last; ++b) covered[((b % kArcBins) + kArcBins) % kArcBins] = true;
    }
  return static_cast<double>(std::count(covered.begin(), covered.end(), true));
}

// One face of a hole measured along its axis (depth from the mouth).
struct FaceStretch {
  int face = -1;
  HoleSegmentKind kind = HoleSegmentKind::Cylinder;
  double from = 0, to = 0;
  bool closes = false;
};

HoleSegmentKind segmentKind(SurfaceType type) {
  switch (type) {
    case SurfaceType::Cone: return HoleSegmentKind::Cone;
    case SurfaceType::Plane: return HoleSegmentKind::Flat;
    case SurfaceType::Torus: return HoleSegmentKind::Torus;
    case SurfaceType::Sphere: return HoleSegmentKind::Sphere;
    default: return HoleSegmentKind::Cylinder;
  }
}

// Two stretches lie on one surface (a face split in halves or in pieces along the axis).
bool sameSurface(const Part& part, const AxisLine& line, const FaceStretch& a, const FaceStretch& b) {
  if (a.kind != b.kind) return false;
  const Face& fa = part.faces[a.face];
  const Face& fb = part.faces[b.face];
  const bool touching = a.from <= b.to + line.line && b.from <= a.to + line.line;
  switch (a.kind) {
    case HoleSegmentKind::Cylinder: return touching && std::abs(fa.radius - fb.radius) <= line.line;
    case HoleSegmentKind::Flat: return std::abs(a.from - b.from) <= line.line;
    case HoleSegmentKind::Cone:
      return touching && (fa.point - fb.point).norm() <= line.line &&
             std::abs(fa.half_angle - fb.half_angle) <= std::asin(std::min(1.0, line.sin_angle)) + 1e-9;
    case HoleSegmentKind::Torus:
      return touching && (fa.point - fb.point).norm() <= line.line && std::abs(fa.radius - fb.radius) <= line.line &&
             std::abs(fa.minor_radius - fb.minor_radius) <= line.line;
    case HoleSegmentKind::Sphere:
      return touching && (fa.point - fb.point).norm() <= line.line && std::abs(fa.radius - fb.radius) <= line.line;
  }
  return false;
}

// The mean distance from the axis of the faces' vertices within `band` of the given depth.
double radiusNear(const Part& part, const FaceIndex& index, const AxisLine& line, const std::vector<int>& faces,
                  double t, double band) {
  double sum = 0;
  int count = 0;
  for (int f : faces)
    for (int v : index.vertices[f]) {
      const Vec3& p = part.mesh.vertices[v];
      if (std::abs(along(line, p) - t) > band) continue;
      sum += radial(line, p);
      ++count;
    }
  return count ? sum / count : 0.0;
}

struct Orientation {
  double t_mouth = 0;  // along the line's axis
  double sign = 1;     // depth = sign * (t_mouth - t)
  double depth(double t) const { return sign * (t_mouth - t); }
  double along(double depth) const { return t_mouth - sign * depth; }
};

// A cone's radius at axial position t of the line.
double coneRadius(const Face& cone, const AxisLine& line, double t) {
  const double apex = along(line, cone.point);
  const double s = (t - apex) * (cone.axis.normalized().dot(line.axis) > 0 ? 1.0 : -1.0);
  return std::max(0.0, s) * std::tan(cone.half_angle);
}

// ---- a hole's description: segments, mouth, bottom, counterbore, countersink ----------------------------------------

std::string signatureOf(const Hole& hole) {
  char text[200];
  std::string bottom = holeBottomName(hole.bottom);
  if (hole.bottom == HoleBottom::Cone) bottom = "cone" + std::to_string(static_cast<int>(std::lround(hole.point_angle_deg)));
  char cb[64] = "cb0", cs[64] = "cs0";
  if (hole.counterbore_diameter > 0)
    std::snprintf(cb, sizeof cb, "cb%.3fx%.3f", hole.counterbore_diameter, hole.counterbore_depth);
  if (hole.countersink_diameter > 0)
    std::snprintf(cs, sizeof cs, "cs%ldx%.3f", std::lround(hole.countersink_angle_deg), hole.countersink_diameter);
  std::snprintf(text, sizeof text, "d%.3f z%.3f %s %s %s", hole.diameter, hole.total_depth, bottom.c_str(), cb, cs);
  return text;
}

// Merges the faces' stretches into segments, sorted from the mouth down.
std::vector<HoleSegment> segmentsOf(const Part& part, const FaceIndex& index, const AxisLine& line,
                                    const Orientation& orientation, std::vector<FaceStretch> stretches) {
  std::sort(stretches.begin(), stretches.end(), [](const FaceStretch& a, const FaceStretch& b) {
    return a.from != b.from ? a.from < b.from : a.face < b.face;
  });
  std::vector<std::vector<FaceStretch>> groups;
  for (const FaceStretch& s : stretches) {
    bool placed = false;
    for (auto& group : groups)
      if (!placed && sameSurface(part, line, group.front(), s)) {
        group.push_back(s);
        placed = true;
      }
    if (!placed) groups.push_back({s});
  }
  std::vector<HoleSegment> segments;
  for (const auto& group : groups) {
    HoleSegment segment;
    segment.kind = group.front().kind;
    segment.from = kInfinity;
    segment.to = -kInfinity;
    bool closes = false;
    for (const FaceStretch& s : group) {
      segment.faces.push_back(s.face);
      segment.from = std::min(segment.from, s.from);
      segment.to = std::max(segment.to, s.to);
      closes = closes || s.closes;
    }
    std::sort(segment.faces.begin(), segment.faces.end());
    const Face& face = part.faces[segment.faces.front()];
    const double band = std::max(line.line, 1e-3 * (segment.to - segment.from));
    switch (segment.kind) {
      case HoleSegmentKind::Cylinder:
        segment.diameter_from = segment.diameter_to = 2 * face.radius;
        break;
      case HoleSegmentKind::Cone:
        segment.diameter_from = 2 * coneRadius(face, line, orientation.along(segment.from));
        segment.diameter_to = 2 * coneRadius(face, line, orientation.along(segment.to));
        break;
      case HoleSegmentKind::Flat: {
        double r_min = kInfinity, r_max = 0;
        for (int f : segment.faces) {
          const Extent e = extentOf(part, index, line, f);
          r_min = std::min(r_min, e.r_min);
          r_max = std::max(r_max, e.r_max);
        }
        segment.from = segment.to = 0.5 * (segment.from + segment.to);
        segment.diameter_from = 2 * r_max;
        segment.diameter_to = closes ? 0.0 : 2 * r_min;
        break;
      }
      default:
        segment.diameter_from = 2 * radiusNear(part, index, line, segment.faces, orientation.along(segment.from), band);
        segment.diameter_to = 2 * radiusNear(part, index, line, segment.faces, orientation.along(segment.to), band);
        break;
    }
    segments.push_back(segment);
  }
  std::sort(segments.begin(), segments.end(), [](const HoleSegment& a, const HoleSegment& b) {
    if (std::abs(a.from - b.from) > 1e-9) return a.from < b.from;
    return a.to < b.to;
  });
  return segments;
}

// Counterbore and countersink at the mouth, bore_start, the bottom's kind, the faces the bore's tool makes.
void describeEnds(Hole& hole, size_t bore, const std::vector<char>& closing_segment, double tolerance) {
  const std::vector<HoleSegment>& segments = hole.segments;
  // The bore runs up while the segment above it is a cylinder of the same diameter that touches it.
  size_t top = bore;
  while (top > 0) {
    const HoleSegment& above = segments[top - 1];
    if (above.kind != HoleSegmentKind::Cylinder || std::abs(above.diameter_from - hole.diameter) > 2 * tolerance ||
        above.to < segments[top].from - tolerance)
      break;
    --top;
  }
  hole.bore_start = segments[top].from;
  double mouth_end = 0;  // where a countersink at the mouth ends
  if (segments.front().kind == HoleSegmentKind::Cone && segments.front().from <= tolerance &&
      segments.front().diameter_from > segments.front().diameter_to + 2 * tolerance) {
    hole.countersink_diameter = segments.front().diameter_from;
    mouth_end = segments.front().to;
  }
  for (size_t s = 0; s + 1 < segments.size() && s < top; ++s) {
    const HoleSegment& wide = segments[s];
    if (wide.kind != HoleSegmentKind::Cylinder || wide.from > mouth_end + tolerance ||
        wide.diameter_from <= hole.diameter + 2 * tolerance)
      continue;
    const HoleSegment& step = segments[s + 1];
    if (step.kind == HoleSegmentKind::Flat && std::abs(step.from - wide.to) <= tolerance) {
      hole.counterbore_diameter = wide.diameter_from;
      hole.counterbore_depth = wide.to;
    }
    break;
  }
  // The bottom: the closing segment below the bore.
  hole.bottom = HoleBottom::Through;
  for (size_t s = 0; s < segments.size(); ++s) {
    if (!closing_segment[s]) continue;
    const HoleSegment& end = segments[s];
    bool corner = false;  // a torus or sphere between the bore's end and the bottom: a rounded floor
    for (size_t k = bore + 1; k < s; ++k)
      corner = corner || segments[k].kind == HoleSegmentKind::Torus || segments[k].kind == HoleSegmentKind::Sphere;
    if (end.kind == HoleSegmentKind::Flat && !corner) {
      hole.bottom = HoleBottom::Flat;
    } else if (end.kind == HoleSegmentKind::Cone && !corner &&
               std::abs(end.diameter_from - hole.diameter) <= 2 * tolerance) {
      hole.bottom = HoleBottom::Cone;
    } else {
      hole.bottom = HoleBottom::Other;
    }
  }
  for (size_t s = top; s <= bore; ++s)
    hole.bore_faces.insert(hole.bore_faces.end(), segments[s].faces.begin(), segments[s].faces.end());
  for (size_t s = 0; s < segments.size(); ++s)
    if (closing_segment[s]) hole.bore_faces.insert(hole.bore_faces.end(), segments[s].faces.begin(), segments[s].faces.end());
  std::sort(hole.bore_faces.begin(), hole.bore_faces.end());
}

}  // namespace

namespace {

// The hole made of `faces` along `line`, or false when they make none (a partial bore, closed at both ends).
// `forced_sign`: 0 finds the mouth; +1 or -1 puts it at the end the line's axis (or its opposite) points to.
bool describeHole(const Part& part, const FaceIndex& index, const AxisLine& line, const std::vector<int>& faces,
                  const HoleOptions& options, Hole& hole, int forced_sign = 0) {
  // Extents along the line, and which faces close an end (the axis pierces them; a cone reaching its apex).
  double t_lo = kInfinity, t_hi = -kInfinity, bore_radius = 0;
  std::vector<Extent> extents;
  for (int f : faces) {
    extents.push_back(extentOf(part, index, line, f));
    t_lo = std::min(t_lo, extents.back().lo);
    t_hi = std::max(t_hi, extents.back().hi);
    if (part.faces[f].type == SurfaceType::Cylinder) bore_radius = std::max(bore_radius, part.faces[f].radius);
  }
  bool closed_lo = false, closed_hi = false;
  std::vector<char> closes(faces.size(), 0);
  for (size_t i = 0; i < faces.size(); ++i) {
    const Face& face = part.faces[faces[i]];
    if (face.type == SurfaceType::Cylinder) continue;
    const bool apex = face.type == SurfaceType::Cone && extents[i].r_min < kApexRatio * bore_radius;
    if (!apex && !axisPierces(part, index, line, faces[i])) continue;
    closes[i] = 1;
    const double middle = 0.5 * (extents[i].lo + extents[i].hi);
    (middle - t_lo < t_hi - middle ? closed_lo : closed_hi) = true;
  }
  if (closed_lo && closed_hi) return false;  // a void inside the part
  Orientation orientation;
  if (forced_sign != 0) {
    if (closed_lo || closed_hi) return false;  // only a through hole opens at both ends
    orientation.sign = forced_sign;
  } else if (closed_lo || closed_hi) {
    orientation.sign = closed_lo ? 1 : -1;
  } else {
    // Through: the mouth is the wider end (a counterbore, a countersink), else the end facing +z, +x, +y.
    double r_lo = 0, r_hi = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
      if (extents[i].lo <= t_lo + line.line) r_lo = std::max(r_lo, extents[i].r_max);
      if (extents[i].hi >= t_hi - line.line) r_hi = std::max(r_hi, extents[i].r_max);
    }
    if (std::abs(r_lo - r_hi) > 2 * line.line) {
      orientation.sign = r_hi > r_lo ? 1 : -1;
    } else {
      const Vec3& a = line.axis;
      const double key = std::abs(a.z()) > 1e-9 ? a.z() : std::abs(a.x()) > 1e-9 ? a.x() : a.y();
      orientation.sign = key > 0 ? 1 : -1;
    }
  }
  orientation.t_mouth = orientation.sign > 0 ? t_hi : t_lo;
  hole = Hole{};
  hole.axis = orientation.sign * line.axis;
  hole.mouth = line.origin + line.axis * orientation.t_mouth;
  std::vector<FaceStretch> stretches;
  for (size_t i = 0; i < faces.size(); ++i) {
    FaceStretch s;
    s.face = faces[i];
    s.kind = segmentKind(part.faces[faces[i]].type);
    const double a = orientation.depth(extents[i].lo), b = orientation.depth(extents[i].hi);
    s.from = std::max(0.0, std::min(a, b));
    s.to = std::max(a, b);
    s.closes = closes[i];
    stretches.push_back(s);
  }
  hole.segments = segmentsOf(part, index, line, orientation, stretches);
  std::vector<char> closing_segment(hole.segments.size(), 0);
  for (size_t s = 0; s < hole.segments.size(); ++s)
    for (size_t i = 0; i < faces.size(); ++i)
      if (closes[i] && std::count(hole.segments[s].faces.begin(), hole.segments[s].faces.end(), faces[i]))
        closing_segment[s] = 1;
  // The main bore: the deepest cylinder.
  size_t bore = hole.segments.size();
  for (size_t s = 0; s < hole.segments.size(); ++s)
    if (hole.segments[s].kind == HoleSegmentKind::Cylinder &&
        (bore == hole.segments.size() || hole.segments[s].to >= hole.segments[bore].to - 1e-9))
      bore = s;
  if (bore == hole.segments.size()) return false;
  hole.arc_deg = arcDegrees(part, index, line, hole.segments[bore].faces);
  if (hole.arc_deg < options.min_arc_deg) return false;
  hole.diameter = hole.segments[bore].diameter_from;
  for (int f : hole.segments[bore].faces) {
    const Face& cylinder = part.faces[f];
    const AxisLine own{cylinder.point, cylinder.axis.normalized(), 0, 0};
    for (int v : index.vertices[f])
      hole.radial_deviation =
          std::max(hole.radial_deviation, std::abs(radial(own, part.mesh.vertices[v]) - cylinder.radius));
  }
  hole.depth = hole.segments[bore].to;
  for (const HoleSegment& s : hole.segments) hole.total_depth = std::max(hole.total_depth, s.to);
  describeEnds(hole, bore, closing_segment, line.line);
  for (size_t s = 0; s < hole.segments.size(); ++s)
    if (closing_segment[s] && hole.bottom == HoleBottom::Cone)
      hole.point_angle_deg = 2 * part.faces[hole.segments[s].faces.front()].half_angle / kDegree;
  if (hole.countersink_diameter > 0)
    hole.countersink_angle_deg = 2 * part.faces[hole.segments.front().faces.front()].half_angle / kDegree;
  hole.faces = faces;
  measureSurroundings(part, hole, options);
  if (hole.bottom == HoleBottom::Through && hole.free_beyond <= 0) {
    // Open on its faces but material right past the far end, within the bore: a bottom that is none of the hole's
    // surfaces (a free-form or an off-axis face).
    hole.bottom = HoleBottom::Other;
  }
  hole.signature = signatureOf(hole);
  return true;
}

AxisLine lineOf(const Part& part, const Face& seed, const HoleOptions& options) {
  AxisLine line;
  line.axis = seed.axis.normalized();
  line.origin = seed.point;
  double angle = options.axis_tolerance_deg, tolerance = options.axis_line_tolerance;
  if (part.face_source == FaceSource::Segmentation) {
    angle = std::max(angle, options.segmented_axis_tolerance_deg);
    tolerance = std::max(tolerance, options.segmented_line_ratio * seed.radius);
  }
  line.sin_angle = std::sin(angle * kDegree);
  line.line = tolerance;
  return line;
}

void checkOptions(const HoleOptions& o) {
  const bool ok = o.diameter_tolerance >= 0 && o.point_angle_tolerance_deg >= 0 && o.axis_tolerance_deg >= 0 &&
                  o.axis_tolerance_deg < 90 && o.axis_line_tolerance >= 0 && o.segmented_axis_tolerance_deg >= 0 &&
                  o.segmented_axis_tolerance_deg < 90 && o.segmented_line_ratio >= 0 && o.min_arc_deg >= 0 &&
                  o.min_arc_deg <= 360 && o.clearance_step > 0 && o.clearance_height > 0 && o.clearance_radius > 0 &&
                  o.clearance_height / o.clearance_step <= 1e5;
  if (!ok) throw InputError("hole options out of range (tolerances >= 0, angles < 90 deg, min_arc_deg in [0, 360], "
                            "clearance step, height and radius > 0)");
}

}  // namespace

Hole reversedHole(const Part& part, const Hole& hole, const HoleOptions& options) {
  checkOptions(options);
  if (hole.bottom != HoleBottom::Through) throw InputError("reversedHole: the hole is not through");
  int seed = -1;
  for (int f : hole.faces)
    if (f >= 0 && f < static_cast<int>(part.faces.size()) && validCylinder(part.faces[f])) {
      seed = f;
      break;
    }
  if (seed < 0) throw InputError("reversedHole: the hole's faces are not this part's");
  const AxisLine line = lineOf(part, part.faces[seed], options);
  Hole reversed;
  const int sign = line.axis.dot(hole.axis) > 0 ? -1 : 1;
  if (!describeHole(part, indexFaces(part), line, hole.faces, options, reversed, sign))
    throw InputError("reversedHole: from its other end the faces make no hole (a partial bore)");
  return reversed;
}

std::vector<Hole> findHoles(const Part& part, const HoleOptions& options) {
  checkOptions(options);
  std::vector<Hole> holes;
  if (part.faces.empty() || part.mesh.triangles.empty()) return holes;
  const FaceIndex index = indexFaces(part);
  std::vector<char> taken(part.faces.size(), 0);
  for (int seed = 0; seed < static_cast<int>(part.faces.size()); ++seed) {
    const Face& face = part.faces[seed];
    if (taken[seed] || !validCylinder(face) || index.triangles[seed].empty()) continue;
    const AxisLine line = lineOf(part, face, options);
    const std::vector<int> faces = growHole(part, index, line, seed, taken);
    for (int f : faces) taken[f] = 1;
    Hole hole;
    if (describeHole(part, index, line, faces, options, hole)) holes.push_back(std::move(hole));
  }
  return holes;
}

}  // namespace art2part
