// Consistent, outward orientation of a triangle mesh (part of repair.h).
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "art2part/geometry/repair.h"

namespace art2part {

namespace {

struct Link {
  int other;
  bool same_direction;  // both triangles run the shared edge the same way: one of them must flip
};

std::vector<std::vector<Link>> linkTriangles(const Mesh& mesh, std::vector<char>& on_open_edge) {
  struct Half {
    int t, a, b;
  };
  std::unordered_map<std::uint64_t, std::vector<Half>> edges;
  edges.reserve(mesh.triangles.size() * 2);
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int e = 0; e < 3; ++e) {
      int a = mesh.triangles[t][e], b = mesh.triangles[t][(e + 1) % 3];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      edges[key].push_back({t, a, b});
    }
  std::vector<std::vector<Link>> links(mesh.triangles.size());
  on_open_edge.assign(mesh.triangles.size(), 0);
  for (const auto& entry : edges) {
    const auto& h = entry.second;
    if (h.size() != 2) {
      for (const Half& x : h) on_open_edge[x.t] = 1;
      continue;
    }
    const bool same = h[0].a == h[1].a;
    links[h[0].t].push_back({h[1].t, same});
    links[h[1].t].push_back({h[0].t, same});
  }
  return links;
}

}  // namespace

// Ray parity along a direction no face of a machined part lies along, so the ray meets edges and vertices only by
// accident.
bool insideTriangles(const Mesh& mesh, const std::vector<int>& tris, const Vec3& p) {
  const Vec3 dir = Vec3(0.8182, 0.3377, 0.4652).normalized();
  int crossings = 0;
  for (int t : tris) {
    const Vec3& a = mesh.corner(t, 0);
    const Vec3 e1 = mesh.corner(t, 1) - a, e2 = mesh.corner(t, 2) - a;
    const Vec3 q = dir.cross(e2);
    const double det = e1.dot(q);
    if (std::abs(det) < 1e-300) continue;
    const Vec3 s = p - a;
    const double u = s.dot(q) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 r = s.cross(e1);
    const double v = dir.dot(r) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(r) / det > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

bool insideClosedMesh(const Mesh& mesh, const Vec3& p) {
  std::vector<int> all(mesh.triangleCount());
  for (int t = 0; t < mesh.triangleCount(); ++t) all[t] = t;
  return insideTriangles(mesh, all, p);
}

namespace {

double componentVolume(const Mesh& mesh, const std::vector<int>& tris) {
  const Vec3 origin = mesh.corner(tris.front(), 0);
  double six = 0.0;
  for (int t : tris) {
    const Vec3 a = mesh.corner(t, 0) - origin, b = mesh.corner(t, 1) - origin, c = mesh.corner(t, 2) - origin;
    six += a.dot(b.cross(c));
  }
  return six / 6.0;
}

void flipTriangle(Triangle& tri) { std::swap(tri[1], tri[2]); }

}  // namespace

int orientConsistently(Mesh& mesh) {
  const int n = mesh.triangleCount();
  std::vector<char> on_open_edge;
  const auto links = linkTriangles(mesh, on_open_edge);

  // Breadth-first propagation of a flip flag from a seed per component.
  std::vector<int> component(n, -1);
  std::vector<char> flip(n, 0);
  std::vector<std::vector<int>> members;
  std::vector<char> closed;
  for (int seed = 0; seed < n; ++seed) {
    if (component[seed] >= 0) continue;
    const int c = static_cast<int>(members.size());
    members.emplace_back();
    closed.push_back(1);
    component[seed] = c;
    std::vector<int> queue{seed};
    for (std::size_t i = 0; i < queue.size(); ++i) {
      const int t = queue[i];
      members[c].push_back(t);
      if (on_open_edge[t]) closed[c] = 0;
      for (const Link& l : links[t]) {
        if (component[l.other] >= 0) continue;
        component[l.other] = c;
        flip[l.other] = flip[t] ^ (l.same_direction ? 1 : 0);
        queue.push_back(l.other);
      }
    }
  }

  // Outward per closed component: positive volume, or negative for a void nested in an odd number of shells.
  std::vector<int> closed_ids;
  for (std::size_t c = 0; c < members.size(); ++c)
    if (closed[c]) closed_ids.push_back(static_cast<int>(c));
  for (std::size_t c = 0; c < members.size(); ++c) {
    auto& tris = members[c];
    for (int t : tris)
      if (flip[t]) flipTriangle(mesh.triangles[t]);
    bool reverse = false;
    if (closed[c]) {
      int depth = 0;
      if (closed_ids.size() <= 64)
        for (int other : closed_ids)
          if (other != static_cast<int>(c) && insideTriangles(mesh, members[other], mesh.corner(tris.front(), 0)))
            ++depth;
      const bool want_positive = depth % 2 == 0;
      reverse = (componentVolume(mesh, tris) > 0) != want_positive;
    } else {
      // An open surface has no inside: keep the winding most of its triangles came with.
      int flipped = 0;
      for (int t : tris) flipped += flip[t];
      reverse = 2 * flipped > static_cast<int>(tris.size());
    }
    if (reverse)
      for (int t : tris) {
        flipTriangle(mesh.triangles[t]);
        flip[t] ^= 1;
      }
  }
  int flipped = 0;
  for (char f : flip) flipped += f;
  return flipped;
}

}  // namespace art2part
