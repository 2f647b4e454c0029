// Small meshes and files made by the tests themselves.
#pragma once

#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>
#include <string>
#include <unistd.h>

#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"

namespace art2part::test {

// An axis-aligned box with its 12 triangles outward, vertices shared.
inline Mesh box(const Vec3& lo, const Vec3& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

// Every triangle with its own three vertices, as an STL file stores them.
inline Mesh unshared(const Mesh& in) {
  Mesh out;
  for (int t = 0; t < in.triangleCount(); ++t) {
    const int base = static_cast<int>(out.vertices.size());
    for (int k = 0; k < 3; ++k) out.vertices.push_back(in.corner(t, k));
    out.triangles.push_back({base, base + 1, base + 2});
  }
  return out;
}

inline void append(Mesh& a, const Mesh& b) {
  const int base = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (Triangle t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

inline void flipAll(Mesh& m) {
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
}

// A folder of its own under /tmp, removed by nobody (CI machines are thrown away).
inline std::string tempDir() {
  char name[] = "/tmp/art2part-test-XXXXXX";
  return mkdtemp(name);
}

// A file's bytes (empty when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The tests' 6 mm flat end mill: 25 mm of flutes, 40 mm stickout, a 30 x 40 mm holder.
inline Tool flat6() {
  Tool t;
  t.id = "flat6";
  t.type = ToolType::Flat;
  t.diameter = 6;
  t.flute_length = 25;
  t.shank_diameter = 6;
  t.stickout = 40;
  t.holder = {{30, 40}};
  return t;
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// Directions spread evenly over the sphere (normalised Gaussian vectors), the same for the same seed.
inline std::vector<Vec3> randomDirections(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count) {
    const Vec3 v(g(rng), g(rng), g(rng));
    if (v.norm() > 1e-6) out.push_back(v.normalized());
  }
  return out;
}

inline std::string asciiStl(const Mesh& m) {
  std::string s = "solid test\n";
  for (int t = 0; t < m.triangleCount(); ++t) {
    const Vec3 n = triangleNormal(m, t);
    s += "facet normal " + std::to_string(n.x()) + " " + std::to_string(n.y()) + " " + std::to_string(n.z()) +
         "\n outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = m.corner(t, k);
      s += "  vertex " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
    }
    s += " endloop\nendfacet\n";
  }
  return s + "endsolid test\n";
}

}  // namespace art2part::test
