// The CPU side of the id renderer: the shared scene and each view's camera (render_scene.h).
#include "render_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

namespace art2part::idrender {

namespace {

double medianArea(const Mesh& mesh) {
  std::vector<double> areas(mesh.triangles.size());
  for (int t = 0; t < mesh.triangleCount(); ++t) areas[t] = triangleArea(mesh, t);
  if (areas.empty()) return 0;
  auto middle = areas.begin() + areas.size() / 2;
  std::nth_element(areas.begin(), middle, areas.end());
  return *middle;
}

// The thesis sizes views so that a typical triangle covers about 50 pixels (3.2.6). A view's side spans the
// bounding-sphere diameter 2R at N pixels, so a pixel is (2R/N)^2 and the median triangle, seen square-on (its
// true area A, its best case), covers A N^2 / 4R^2 pixels: N = 2R sqrt(ppt / A), clamped to [64, max_resolution].
// Triangles seen obliquely cover less: ones smaller than a pixel may fall between pixel centres and be missed.
int chooseResolution(const Mesh& mesh, double radius, const RenderVisibilityOptions& options) {
  if (options.resolution > 0) return options.resolution;
  const int max_resolution = std::max(64, options.max_resolution);
  const double area = medianArea(mesh);
  if (!(area > 0)) return max_resolution;
  const double n = std::ceil(2 * radius * std::sqrt(std::max(options.pixels_per_triangle, 0.0) / area));
  return static_cast<int>(std::clamp(n, 64.0, double(max_resolution)));
}

// Culling back faces gives the same pixels as drawing them when the surface is closed and oriented outwards: a
// line of sight from outside first meets the part where it enters it, on a front face, so a back face is never
// the nearest surface. It holds when every directed edge (a, b) is matched by exactly one (b, a) and every
// edge-connected shell encloses a positive volume. Anything else (an open mesh, an inside-out shell, a void)
// draws back faces too. Culling skips rasterising about half the triangles: a third less time per view.
bool backFacesNeverShow(const Mesh& mesh) {
  const int count = mesh.triangleCount();
  std::vector<std::pair<std::uint64_t, int>> edges;  // (a << 32 | b, triangle), sorted
  edges.reserve(3 * std::size_t(count));
  auto key = [](int a, int b) { return std::uint64_t(std::uint32_t(a)) << 32 | std::uint32_t(b); };
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) edges.emplace_back(key(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]), t);
  std::sort(edges.begin(), edges.end());
  std::vector<int> shell(count);  // union-find over triangles sharing an edge
  for (int t = 0; t < count; ++t) shell[t] = t;
  auto find = [&](int t) {
    while (shell[t] != t) t = shell[t] = shell[shell[t]];
    return t;
  };
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::uint64_t e = edges[i].first, reverse = e << 32 | e >> 32;
    if (i > 0 && edges[i - 1].first == e) return false;  // an edge run twice the same way
    auto twin = std::lower_bound(edges.begin(), edges.end(), std::make_pair(reverse, -1));
    if (twin == edges.end() || twin->first != reverse) return false;  // a boundary edge
    shell[find(edges[i].second)] = find(twin->second);
  }
  std::vector<double> volume(count, 0.0);  // six times each shell's signed volume, about the first vertex
  const Vec3 origin = mesh.vertices[mesh.triangles[0][0]];
  for (int t = 0; t < count; ++t) {
    const Vec3 a = mesh.corner(t, 0) - origin, b = mesh.corner(t, 1) - origin, c = mesh.corner(t, 2) - origin;
    volume[find(t)] += a.dot(b.cross(c));
  }
  for (int t = 0; t < count; ++t)
    if (find(t) == t && !(volume[t] > 0)) return false;
  return true;
}

}  // namespace

Scene prepareScene(const Mesh& mesh, const RenderVisibilityOptions& options) {
  Scene scene;
  const Box box = boundingBox(mesh);
  const Vec3 centre = box.center();
  for (int i = 0; i < 8; ++i)
    scene.corners.emplace_back(Vec3(i & 1 ? box.max.x() : box.min.x(), i & 2 ? box.max.y() : box.min.y(),
                                    i & 4 ? box.max.z() : box.min.z()) - centre);
  double radius = 0;
  for (const Triangle& t : mesh.triangles)
    for (int v : t) {
      if (v < 0 || v >= static_cast<int>(mesh.vertices.size()))
        throw std::invalid_argument("renderVisibility: triangle refers to a missing vertex");
      radius = std::max(radius, (mesh.vertices[v] - centre).norm());
    }
  // A small margin keeps corners on the sphere off the clip planes, where float rounding could cut them.
  scene.radius = std::max(radius, 1e-9) * 1.001;
  scene.positions.reserve(3 * mesh.vertices.size());
  for (const Vec3& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) scene.positions.push_back(static_cast<float>(v[k] - centre[k]));
  scene.indices.reserve(3 * mesh.triangles.size());
  scene.normals.reserve(mesh.triangles.size());
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    for (int v : mesh.triangles[t]) scene.indices.push_back(static_cast<unsigned>(v));
    scene.normals.push_back(triangleNormal(mesh, t));
  }
  scene.resolution = chooseResolution(mesh, scene.radius, options);
  scene.cull = backFacesNeverShow(mesh);
  scene.outlines = options.outlines;
  return scene;
}

View makeView(const Vec3& d, const Scene& scene) {
  const Vec3 back = d.normalized();
  Eigen::Index least = 0;  // the axis least aligned with d makes the best-conditioned cross product
  back.cwiseAbs().minCoeff(&least);
  const Vec3 right = Vec3::Unit(least).cross(back).normalized();
  const Vec3 up = back.cross(right);
  View view;
  const Vec3 axes[3] = {right, up, back};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) view.rows[3 * r + c] = static_cast<float>(axes[r][c] / scene.radius);
  // Reading back only the box's shadow saves read-back and scanning, most for long thin parts.
  double lo[2] = {1, 1}, hi[2] = {-1, -1};
  for (const Vec3& corner : scene.corners)
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], corner.dot(axes[k]) / scene.radius);
      hi[k] = std::max(hi[k], corner.dot(axes[k]) / scene.radius);
    }
  const int n = scene.resolution;
  auto pixel = [n](double ndc) { return std::clamp(static_cast<int>(std::floor((ndc + 1) / 2 * n)), 0, n); };
  view.x = std::max(pixel(lo[0]) - 1, 0);  // a pixel of slack either side for rounding
  view.y = std::max(pixel(lo[1]) - 1, 0);
  view.width = std::min(pixel(hi[0]) + 2, n) - view.x;
  view.height = std::min(pixel(hi[1]) + 2, n) - view.y;
  return view;
}

}  // namespace art2part::idrender
