// Scoring a segmentation against reference faces (the B-rep faces of a STEP file, tessellated).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "art2part/geometry/segmentation.h"

namespace art2part {

namespace {

constexpr double kDirectionTolerance = 1e-6;  // unit vectors and angles (rad)
constexpr double kRelativeLength = 1e-6;      // of the largest length in the reference faces

// Lengths in the faces (offsets, points, radii), to make the "same surface" tolerance relative to the part.
double lengthScale(const std::vector<Face>& faces) {
  double scale = 1.0;
  for (const Face& f : faces)
    scale = std::max({scale, std::abs(f.offset), f.point.norm(), f.radius, f.minor_radius});
  return scale;
}

bool sameLine(const Vec3& axis_a, const Vec3& point_a, const Vec3& axis_b, const Vec3& point_b, double length) {
  if (axis_a.cross(axis_b).norm() > kDirectionTolerance) return false;
  const Vec3 d = point_b - point_a;
  return (d - axis_a * axis_a.dot(d)).norm() <= length;
}

// Whether two reference faces lie on one surface (same side of it: concavity and plane normals must agree).
bool sameSurface(const Face& a, const Face& b, double length) {
  if (a.type != b.type || a.concave != b.concave) return false;
  switch (a.type) {
    case SurfaceType::Plane:
      return (a.normal - b.normal).norm() <= kDirectionTolerance && std::abs(a.offset - b.offset) <= length;
    case SurfaceType::Cylinder:
      return sameLine(a.axis, a.point, b.axis, b.point, length) && std::abs(a.radius - b.radius) <= length;
    case SurfaceType::Cone:
      return (a.axis - b.axis).norm() <= kDirectionTolerance && (a.point - b.point).norm() <= length &&
             std::abs(a.half_angle - b.half_angle) <= kDirectionTolerance;
    case SurfaceType::Sphere:
      return (a.point - b.point).norm() <= length && std::abs(a.radius - b.radius) <= length;
    case SurfaceType::Torus:
      return a.axis.cross(b.axis).norm() <= kDirectionTolerance && (a.point - b.point).norm() <= length &&
             std::abs(a.radius - b.radius) <= length && std::abs(a.minor_radius - b.minor_radius) <= length;
    case SurfaceType::Other:
      return false;  // nothing to compare a free-form surface by
  }
  return false;
}

// Triangle counts of every (segment, face) pair that occurs.
using PairCounts = std::unordered_map<std::uint64_t, int>;

std::uint64_t pairKey(int segment, int face) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(segment)) << 32) | static_cast<std::uint32_t>(face);
}

PairCounts countPairs(const std::vector<int>& segment_of, const std::vector<int>& face_of) {
  PairCounts counts;
  for (std::size_t t = 0; t < segment_of.size(); ++t)
    if (segment_of[t] >= 0 && face_of[t] >= 0) ++counts[pairKey(segment_of[t], face_of[t])];
  return counts;
}

// For each segment the face holding most of its triangles, and for each face the segment holding most of its
// triangles (ties to the lower id, so the result does not depend on hash order).
struct Majorities {
  std::vector<int> face_of_segment, segment_of_face;
};

Majorities majorities(const PairCounts& counts, int segments, int faces) {
  Majorities m;
  m.face_of_segment.assign(segments, -1);
  m.segment_of_face.assign(faces, -1);
  std::vector<int> best_face_count(segments, 0), best_segment_count(faces, 0);
  auto better = [](int count, int id, int best_count, int best_id) {
    return count > best_count || (count == best_count && (best_id < 0 || id < best_id));
  };
  for (const auto& entry : counts) {
    const int s = static_cast<int>(entry.first >> 32), f = static_cast<int>(entry.first & 0xffffffffu);
    const int c = entry.second;
    if (better(c, f, best_face_count[s], m.face_of_segment[s])) {
      best_face_count[s] = c;
      m.face_of_segment[s] = f;
    }
    if (better(c, s, best_segment_count[f], m.segment_of_face[f])) {
      best_segment_count[f] = c;
      m.segment_of_face[f] = s;
    }
  }
  return m;
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Reference faces on one surface whose triangles mostly went to the same segment are one face split by the
// modeller (two half-cylinders, a plane cut in two). Faces on one surface that the segmentation kept apart (the tops
// of two separate bosses) stay apart: a segment is connected, so sharing one means the faces touch.
std::vector<int> mergeSplitFaces(const std::vector<Face>& faces, const std::vector<int>& segment_of_face,
                                 int* group_count) {
  const int n = static_cast<int>(faces.size());
  const double length = kRelativeLength * lengthScale(faces);
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::unordered_map<int, std::vector<int>> faces_by_segment;
  for (int f = 0; f < n; ++f)
    if (segment_of_face[f] >= 0) faces_by_segment[segment_of_face[f]].push_back(f);
  for (const auto& entry : faces_by_segment) {
    const std::vector<int>& group = entry.second;
    for (std::size_t i = 0; i < group.size(); ++i)
      for (std::size_t j = i + 1; j < group.size(); ++j)
        if (sameSurface(faces[group[i]], faces[group[j]], length))
          parent[findRoot(parent, group[j])] = findRoot(parent, group[i]);
  }
  std::vector<int> merged(n, -1), id_of_root(n, -1);
  int next = 0;
  for (int f = 0; f < n; ++f) {
    const int root = findRoot(parent, f);
    if (id_of_root[root] < 0) id_of_root[root] = next++;
    merged[f] = id_of_root[root];
  }
  *group_count = next;
  return merged;
}

}  // namespace

SegmentationScore scoreSegmentation(const std::vector<int>& segment_of, const std::vector<Face>& segments,
                                    const std::vector<int>& face_of, const std::vector<Face>& faces) {
  if (segment_of.size() != face_of.size())
    throw std::invalid_argument("scoreSegmentation: segment and face maps cover different triangle counts");
  const int segment_count = static_cast<int>(segments.size()), face_count = static_cast<int>(faces.size());
  for (std::size_t t = 0; t < segment_of.size(); ++t)
    if (segment_of[t] >= segment_count || face_of[t] >= face_count)
      throw std::invalid_argument("scoreSegmentation: a triangle names a segment or face that does not exist");

  SegmentationScore score;
  score.segments = segment_count;
  const std::size_t n = segment_of.size();
  if (n == 0) return score;

  const Majorities raw = majorities(countPairs(segment_of, face_of), segment_count, face_count);
  int group_count = 0;
  const std::vector<int> group_of_face = mergeSplitFaces(faces, raw.segment_of_face, &group_count);
  score.reference_faces = group_count;

  std::vector<int> group_of(n, -1);
  for (std::size_t t = 0; t < n; ++t)
    if (face_of[t] >= 0) group_of[t] = group_of_face[face_of[t]];
  const Majorities merged = majorities(countPairs(segment_of, group_of), segment_count, group_count);

  std::size_t matched = 0, same_type = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const int s = segment_of[t], g = group_of[t];
    if (s < 0 || g < 0) continue;
    if (merged.face_of_segment[s] == g && merged.segment_of_face[g] == s) ++matched;
    if (segments[s].type == faces[face_of[t]].type) ++same_type;
  }
  score.matched_fraction = static_cast<double>(matched) / static_cast<double>(n);
  score.type_agreement = static_cast<double>(same_type) / static_cast<double>(n);
  return score;
}

}  // namespace art2part
