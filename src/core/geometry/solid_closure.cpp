#include "art2part/geometry/solid_closure.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/repair.h"

namespace art2part {

namespace {

// Per undirected edge (lower index first): how often triangles use it low -> high minus high -> low.
std::unordered_map<std::uint64_t, int> edgeUses(const Mesh& mesh) {
  std::unordered_map<std::uint64_t, int> uses;
  uses.reserve(mesh.triangles.size() * 2);
  for (const Triangle& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      const int a = t[i], b = t[(i + 1) % 3];
      if (a == b) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      uses[key] += a < b ? 1 : -1;
    }
  return uses;
}

// The principal axis nearest to minus the mesh's vector area (the sum of its area-weighted normals: zero for a closed
// mesh, the outline's oriented area for an open one; a relief's points up, so its open side is down). -z when
// there is none to speak of.
Vec3 openSide(const Mesh& mesh) {
  Vec3 area = Vec3::Zero();
  double total = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 n = (mesh.corner(t, 1) - mesh.corner(t, 0)).cross(mesh.corner(t, 2) - mesh.corner(t, 0));
    area += n;
    total += n.norm();
  }
  if (area.norm() <= 1e-6 * total) return -Vec3::UnitZ();
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(area[k]) > std::abs(area[axis])) axis = k;
  Vec3 d = Vec3::Zero();
  d[axis] = area[axis] > 0 ? -1 : 1;
  return d;
}

}  // namespace

int boundaryChainEdges(const Mesh& mesh) {
  int n = 0;
  for (const auto& [key, count] : edgeUses(mesh)) n += count != 0 ? 1 : 0;
  return n;
}

SolidClosure closeOpenMesh(const Mesh& mesh) {
  SolidClosure c;
  c.mesh = mesh;
  const auto uses = edgeUses(mesh);
  for (const auto& [key, count] : uses) c.boundary_edges += count != 0 ? 1 : 0;
  if (c.boundary_edges == 0) return c;

  c.direction = openSide(mesh);
  c.floor = -std::numeric_limits<double>::infinity();
  for (const Vec3& p : mesh.vertices) c.floor = std::max(c.floor, p.dot(c.direction));
  // Each vertex's shadow on the floor: the vertex itself when it lies there (so the chain closes by indices too).
  std::vector<int> shadow(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3& p = mesh.vertices[v];
    const Vec3 q = p + (c.floor - p.dot(c.direction)) * c.direction;
    if (q == p) {
      shadow[v] = static_cast<int>(v);
    } else {
      shadow[v] = static_cast<int>(c.mesh.vertices.size());
      c.mesh.vertices.push_back(q);
    }
  }
  auto floorOf = [&shadow](int v) { return shadow[v]; };
  auto onFloor = [&shadow](int v) { return shadow[v] == v; };

  // Skirt: the boundary edge a -> b (as its triangles use it, `count` times net) swept to the floor as the quad
  // b, a, a', b', which uses b -> a against it and a' -> b' against the cap.
  for (const auto& [key, count] : uses) {
    if (count == 0) continue;
    int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    if (count < 0) std::swap(a, b);
    if (onFloor(a) && onFloor(b)) continue;  // the quad has no area
    for (int k = 0; k < std::abs(count); ++k) {
      c.mesh.triangles.push_back({b, a, floorOf(a)});
      c.mesh.triangles.push_back({b, floorOf(a), floorOf(b)});
      c.skirt_triangles += 2;
    }
  }
  // Cap: every triangle not edge-on to the direction, projected and reversed.
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 normal = (mesh.vertices[tri[1]] - mesh.vertices[tri[0]]).cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
    if (normal.dot(c.direction) == 0) continue;
    c.mesh.triangles.push_back({floorOf(tri[2]), floorOf(tri[1]), floorOf(tri[0])});
    ++c.cap_triangles;
  }
  return c;
}

Part machiningSolid(const Part& part, SolidClosure* closure) {
  SolidClosure c = closeOpenMesh(part.mesh);
  Part solid = part;
  if (!c.closed()) {
    solid.mesh = c.mesh;
    solid.triangle_face.resize(solid.mesh.triangles.size(), -1);
    solid.adjacency = buildAdjacency(solid.mesh);
    solid.check = checkMesh(solid.mesh);
  }
  if (closure) *closure = std::move(c);
  return solid;
}

}  // namespace art2part
