// Special directions of a part (thesis 3.2.2): plane normals, cylinder and cone axes, and long straight edges,
// which a uniform sampling of the sphere would miss, and their insertion into a DirectionSet.
#include "art2part/sphere/special_directions.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace art2part {
namespace {

// Consecutive mesh edges belong to one straight line when they turn by less than this. Tessellated straight B-rep
// edges are collinear to rounding, float STL vertices to about 1e-5 rad; tessellated arcs turn by degrees.
constexpr double kCollinearAngle = 1e-3;

void addBothSenses(std::vector<SpecialDirection>& out, const Vec3& axis, double weight) {
  out.push_back({axis, weight});
  out.push_back({-axis, weight});
}

double totalFaceArea(const Part& part) {
  double total = 0.0;
  for (const Face& f : part.faces) total += f.area;
  return total > 0.0 ? total : surfaceArea(part.mesh);
}

void addFaceDirections(const Part& part, const SpecialDirectionOptions& options, std::vector<SpecialDirection>& out) {
  const double min_area = options.min_face_fraction * totalFaceArea(part);
  for (const Face& f : part.faces) {
    if (f.area <= 0.0 || f.area < min_area) continue;
    if (f.type == SurfaceType::Plane && options.plane_normals && f.normal.norm() > 0.5)
      out.push_back({f.normal.normalized(), f.area});
    const bool axial = f.type == SurfaceType::Cylinder || f.type == SurfaceType::Cone;
    if (axial && options.cylinder_axes && f.axis.norm() > 0.5) addBothSenses(out, f.axis.normalized(), f.area);
  }
}

struct Segment {
  int a, b;  // vertex indices
};

// Every sharp (convex or concave) manifold edge once.
std::vector<Segment> sharpSegments(const Part& part) {
  std::vector<Segment> out;
  const Adjacency& adj = part.adjacency;
  const int n = std::min<int>(part.mesh.triangleCount(), static_cast<int>(adj.klass.size()));
  for (int t = 0; t < n; ++t)
    for (int e = 0; e < 3; ++e) {
      const EdgeClass k = adj.klass[t][e];
      const int other = adj.neighbour[t][e];
      if ((k != EdgeClass::Convex && k != EdgeClass::Concave) || other < t) continue;  // the other side adds it
      const Triangle& tri = part.mesh.triangles[t];
      if (tri[e] != tri[(e + 1) % 3]) out.push_back({tri[e], tri[(e + 1) % 3]});
    }
  return out;
}

// Chains sharp segments into straight lines, each segment in one line.
class LineChainer {
 public:
  LineChainer(const Mesh& mesh, std::vector<Segment> segments)
      : mesh_(mesh), segments_(std::move(segments)), used_(segments_.size(), 0) {
    for (int i = 0; i < static_cast<int>(segments_.size()); ++i) {
      at_[segments_[i].a].push_back(i);
      at_[segments_[i].b].push_back(i);
    }
  }

  // Calls found(unit direction, length) for every line.
  template <typename Found>
  void run(Found found) {
    for (int i = 0; i < static_cast<int>(segments_.size()); ++i) {
      if (used_[i]) continue;
      used_[i] = 1;
      int start = segments_[i].a, end = segments_[i].b;
      const Vec3 along = mesh_.vertices[end] - mesh_.vertices[start];
      if (along.norm() <= 0.0) continue;
      end = extend(start, end);
      start = extend(end, start);
      const Vec3 line = mesh_.vertices[end] - mesh_.vertices[start];
      found(line.normalized(), line.norm());
    }
  }

 private:
  // Walks on from `end` away from `start` while some unused segment continues the line; returns the last vertex.
  // The test is against the whole line so far, not the last segment, so a finely tessellated arc cannot creep on.
  int extend(int start, int end) {
    const double min_cos = std::cos(kCollinearAngle);
    for (;;) {
      const Vec3 dir = (mesh_.vertices[end] - mesh_.vertices[start]).normalized();
      int next_segment = -1, next_vertex = -1;
      double best = min_cos;
      for (int s : at_[end]) {
        if (used_[s]) continue;
        const int w = segments_[s].a == end ? segments_[s].b : segments_[s].a;
        const Vec3 step = mesh_.vertices[w] - mesh_.vertices[end];
        if (step.norm() <= 0.0) continue;
        const double c = step.normalized().dot(dir);
        if (c > best) best = c, next_segment = s, next_vertex = w;
      }
      if (next_segment < 0) return end;
      used_[next_segment] = 1;
      end = next_vertex;
    }
  }

  const Mesh& mesh_;
  std::vector<Segment> segments_;
  std::vector<char> used_;
  std::unordered_map<int, std::vector<int>> at_;  // segments at each vertex
};

void addEdgeDirections(const Part& part, const SpecialDirectionOptions& options, std::vector<SpecialDirection>& out) {
  const double min_length = options.min_edge_fraction * boundingBox(part.mesh).diagonal();
  LineChainer chainer(part.mesh, sharpSegments(part));
  chainer.run([&](const Vec3& dir, double length) {
    if (length >= min_length && length > 0.0) addBothSenses(out, dir, length);
  });
}

bool byWeightDescending(const SpecialDirection& a, const SpecialDirection& b) { return a.weight > b.weight; }

// Heaviest first, each joins the first kept direction within the merge angle (which is heavier, so the kept
// direction stays exactly the heavier one's) or becomes a new one.
std::vector<SpecialDirection> merge(std::vector<SpecialDirection> candidates, double merge_angle) {
  std::stable_sort(candidates.begin(), candidates.end(), byWeightDescending);
  const double min_cos = std::cos(merge_angle);
  std::vector<SpecialDirection> kept;
  for (const SpecialDirection& s : candidates) {
    auto near = std::find_if(kept.begin(), kept.end(),
                             [&](const SpecialDirection& k) { return k.direction.dot(s.direction) >= min_cos; });
    if (near != kept.end())
      near->weight += s.weight;
    else
      kept.push_back(s);
  }
  std::stable_sort(kept.begin(), kept.end(), byWeightDescending);  // summed weights can change the order
  return kept;
}

bool sameDirection(const Vec3& a, const Vec3& b, double merge_angle) { return a.dot(b) >= std::cos(merge_angle); }

// True when one of cell c's directions is already within the merge angle of d.
bool cellHasDirection(const DirectionSet& set, int c, const Vec3& d, double merge_angle) {
  if (set.special[c] && sameDirection(set.directions[c], d, merge_angle)) return true;
  for (int i = set.cellCount(); i < set.size(); ++i)
    if (set.cell_of[i] == c && sameDirection(set.directions[i], d, merge_angle)) return true;
  return false;
}

}  // namespace

std::vector<SpecialDirection> specialDirections(const Part& part, const SpecialDirectionOptions& options) {
  std::vector<SpecialDirection> candidates;
  addFaceDirections(part, options, candidates);
  if (options.linear_edges) addEdgeDirections(part, options, candidates);
  return merge(std::move(candidates), options.merge_angle);
}

void insertSpecialDirections(DirectionSet& set, const std::vector<SpecialDirection>& special) {
  // insertSpecialDirections takes no options: directions from specialDirections are already merge_angle apart, so
  // the default angle only stops the same direction (a second call, or a list with repeats) going in twice.
  const double merge_angle = SpecialDirectionOptions{}.merge_angle;
  std::vector<SpecialDirection> order = special;
  std::stable_sort(order.begin(), order.end(), byWeightDescending);
  for (const SpecialDirection& s : order) {
    if (s.direction.norm() <= 0.0) continue;
    const Vec3 d = s.direction.normalized();
    const int c = cellContaining(set, d);
    if (cellHasDirection(set, c, d, merge_angle)) continue;
    if (!set.special[c]) {  // the cell still has its centroid: the special direction takes its place
      set.directions[c] = d;
      set.special[c] = 1;
      continue;
    }
    set.directions.push_back(d);
    set.cell_of.push_back(c);
    set.special.push_back(1);
  }
}

}  // namespace art2part
