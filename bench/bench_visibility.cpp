// Visibility benchmarks (issue 3): speed of both backends beside the naive 1024 x 1024 OSMesa loop, linear scaling
// in triangles and directions, and the agreement of the backends on every shared part.
//   bench_visibility [speed [default|ray]|scaling|accuracy [PART [LEVEL]]|judge [PART [LEVEL [SAMPLES]]]|all]
// (default all; PART a file name in shared/parts, "" for every part). judge asks the exact oracle about sampled pairs:
// where the backends disagree, which is right, and how often each is wrong on pairs taken at random.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/visibility/analysis.h"
#include "art2part/visibility/cones.h"
#include "art2part/visibility/exact_visibility.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_visibility [speed [default|ray] | scaling | accuracy [PART [LEVEL]] | judge [PART [LEVEL [SAMPLES]]] |\n"
    "                  all [PART [LEVEL]]]\n"
    "  default all (PART and LEVEL for its accuracy); PART a file name in shared/parts, \"\" for every part\n";
const std::string kParts = ART2PART_SHARED_PARTS;
constexpr double kPi = 3.14159265358979323846;

double secondsOf(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void printRate(const char* what, int triangles, int directions, double seconds) {
  const double pairs = static_cast<double>(triangles) * directions;
  std::printf("  %-34s %7d tri x %5d dir  %8.2f s  %12.0f pairs/s\n", what, triangles, directions, seconds,
              pairs / seconds);
}

// only: "" for every figure, "default" for the default ray backend alone, "ray" for the ray figures.
void speed(const std::string& only) {
  std::printf("speed: 100k-triangle part x 1024 directions (level 4), 2 threads unless said\n");
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc_fine_tess.stl");
  const DirectionSet set = sampleSphere(4);
  const int T = part.mesh.triangleCount(), D = set.size();
  double s = secondsOf([&] { rayVisibility(part.mesh, set.directions, defaultRayOptions()); });
  printRate("ray, 1 sample + edges [default]", T, D, s);
  if (only == "default") return;
  s = secondsOf([&] { rayVisibility(part.mesh, set.directions, withEdgeRefinement()); });
  printRate("ray, 4 samples + edges", T, D, s);
  s = secondsOf([&] { rayVisibility(part.mesh, set.directions); });
  printRate("ray (Embree), 4 samples", T, D, s);
  RayVisibilityOptions one;
  one.samples_per_triangle = 1;
  s = secondsOf([&] { rayVisibility(part.mesh, set.directions, one); });
  printRate("ray (Embree), 1 sample", T, D, s);
  if (only == "ray") return;
  RenderVisibilityOptions render;
  s = secondsOf([&] { renderVisibility(part.mesh, set.directions, render); });
  printRate("render (OSMesa ids), auto resolution", T, D, s);
  // The naive loop: 1024 x 1024 per view, one context. Timed on 64 directions; the rate is what counts.
  RenderVisibilityOptions naive;
  naive.resolution = 1024;
  naive.threads = 1;
  const std::vector<Vec3> some(set.directions.begin(), set.directions.begin() + 64);
  s = secondsOf([&] { renderVisibility(part.mesh, some, naive); });
  printRate("naive render 1024x1024, 1 thread", T, 64, s);
  std::printf("  naive loop extrapolated to %d directions: %.1f s\n", D, s * D / 64.0);
}

// Every triangle split in four at its edges' midpoints (shared between neighbours): the same shape, 4x the triangles.
Mesh subdivided(const Mesh& in) {
  Mesh out;
  out.vertices = in.vertices;
  std::map<std::pair<int, int>, int> middle;
  auto mid = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    const auto it = middle.find(key);
    if (it != middle.end()) return it->second;
    out.vertices.push_back(0.5 * (in.vertices[a] + in.vertices[b]));
    return middle[key] = static_cast<int>(out.vertices.size()) - 1;
  };
  for (const Triangle& t : in.triangles) {
    const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
    out.triangles.push_back({t[0], ab, ca});
    out.triangles.push_back({ab, t[1], bc});
    out.triangles.push_back({ca, bc, t[2]});
    out.triangles.push_back({ab, bc, ca});
  }
  return out;
}

void scaling() {
  std::printf("scaling: triangles (STEP tessellated finer) and directions (sphere level), default ray backend\n");
  const DirectionSet set = sampleSphere(4);
  for (double tolerance : {2.0, 0.5, 0.15}) {
    LoadOptions load;
    load.chordal_tolerance = tolerance;
    const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc.stp", load);
    const double s = secondsOf([&] { rayVisibility(part.mesh, set.directions, defaultRayOptions()); });
    printRate(("CTC 2, chordal " + std::to_string(tolerance).substr(0, 4) + " mm").c_str(),
              part.mesh.triangleCount(), set.size(), s);
  }
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc_fine_tess.stl");
  // Triangles over a wider range: CTC-01 (6.7k), the fine STL (122k), the fine STL subdivided (489k), level 3.
  const DirectionSet level3 = sampleSphere(3);
  const Mesh small = loadPart(kParts + "/nist_ctc_01_asme1_rd.stp").mesh, large = subdivided(part.mesh);
  for (const auto& [name, mesh] : {std::pair<const char*, const Mesh*>{"CTC 1, level 3", &small},
                                   {"fine tessellation, level 3", &part.mesh},
                                   {"fine tessellation split in 4, level 3", &large}}) {
    const double s = secondsOf([&] { rayVisibility(*mesh, level3.directions, defaultRayOptions()); });
    printRate(name, mesh->triangleCount(), level3.size(), s);
  }
  for (int level : {3, 4, 5}) {
    const DirectionSet dirs = sampleSphere(level);
    const double s = secondsOf([&] { rayVisibility(part.mesh, dirs.directions, defaultRayOptions()); });
    printRate(("fine tessellation, level " + std::to_string(level)).c_str(), part.mesh.triangleCount(), dirs.size(), s);
  }
}

const char* const kAllParts[] = {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp",
                                 "featuretype.STEP", "ktoolcav.stl", "mount_rush.stl",
                                 "Ailette001Solid-nohole-decimated-smoothed.stl", "nist_ctc_02_asme1_rc_fine_tess.stl"};

// Both backends' maps of one part at one level (special directions, no side correction), as the issue compares them.
struct BackendMaps {
  Part part;
  VisibilityResult ray, render;
  double ray_seconds = 0, render_seconds = 0;
};

BackendMaps backendMaps(const std::string& name, int level) {
  BackendMaps maps{loadPart(kParts + "/" + name), {}, {}};
  VisibilityOptions options;
  options.level = level;
  options.side_correction = false;
  maps.ray_seconds = secondsOf([&] { maps.ray = analyseVisibility(maps.part, options); });
  options.backend = VisibilityBackend::Render;
  maps.render_seconds = secondsOf([&] { maps.render = analyseVisibility(maps.part, options); });
  return maps;
}

// Whether the pair is compared: not within 2 degrees of grazing.
bool compared(const Vec3& n, const Vec3& d) { return std::abs(n.dot(d)) >= std::sin(2.0 * kPi / 180.0); }

void accuracy(const std::string& only, int level) {
  std::printf("accuracy: ray vs render at level %d with special directions, no side correction; pairs within 2 deg of "
              "grazing left out; lost = seen by a dense ray reference (7 samples + edges) from some direction, by the "
              "backend from none\n", level);
  for (const char* name : kAllParts) {
    if (!only.empty() && only != name) continue;
    const BackendMaps maps = backendMaps(name, level);
    const Mesh& mesh = maps.part.mesh;
    const std::vector<Vec3>& directions = maps.ray.directions.directions;
    RayVisibilityOptions dense = withEdgeRefinement();
    dense.samples_per_triangle = 7;
    dense.rescue_unseen = false;  // the plain dense model: the rescue's extra rays are the default's own
    const VisibilityMap reference = rayVisibility(mesh, directions, dense);
    long long pairs = 0, ray_only = 0, render_only = 0;
    for (int t = 0; t < mesh.triangleCount(); ++t) {
      const Vec3 n = triangleNormal(mesh, t);
      for (int d = 0; d < maps.ray.map.directions(); ++d) {
        if (!compared(n, directions[d])) continue;
        ++pairs;
        const bool a = maps.ray.map.bits.get(t, d), b = maps.render.map.bits.get(t, d);
        ray_only += a && !b;
        render_only += b && !a;
      }
    }
    int lost_ray = 0, lost_render = 0;
    for (int t = 0; t < mesh.triangleCount(); ++t) {
      if (reference.bits.rowCount(t) == 0) continue;
      lost_ray += maps.ray.map.bits.rowCount(t) == 0;
      lost_render += maps.render.map.bits.rowCount(t) == 0;
    }
    std::printf("  %-46s %7d tri %5d dir  agreement %.5f  (ray only %lld, render only %lld)  lost: ray %d, render %d"
                "  [ray %.1f s, render %.1f s]\n",
                name, mesh.triangleCount(), maps.ray.map.directions(),
                1.0 - static_cast<double>(ray_only + render_only) / pairs, ray_only, render_only, lost_ray,
                lost_render, maps.ray_seconds, maps.render_seconds);
  }
}

// The triangle's projection along d in pixels of a view of the given resolution over the bounding sphere
// (radius), and its thinnest width (twice the projected area over the longest projected side).
std::pair<double, double> projectedPixels(const Mesh& mesh, int t, const Vec3& d, double pixel) {
  const Vec3 a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
  auto flat = [&d](const Vec3& v) { return Vec3(v - v.dot(d) * d); };
  const double area = 0.5 * flat(b - a).cross(flat(c - a)).norm();
  const double longest = std::max({flat(b - a).norm(), flat(c - b).norm(), flat(a - c).norm()});
  return {area / (pixel * pixel), longest > 0 ? 2 * area / longest / pixel : 0.0};
}

// The render backend's pixel size on this part, as render_scene.cpp chooses the resolution (defaults).
double renderPixel(const Mesh& mesh) {
  const Vec3 centre = boundingBox(mesh).center();
  double radius = 0;
  for (const Vec3& v : mesh.vertices) radius = std::max(radius, (v - centre).norm());
  radius *= 1.001;
  std::vector<double> areas;
  for (int t = 0; t < mesh.triangleCount(); ++t) areas.push_back(triangleArea(mesh, t));
  std::nth_element(areas.begin(), areas.begin() + areas.size() / 2, areas.end());
  const double median = areas[areas.size() / 2];
  const double n = median > 0 ? std::clamp(std::ceil(2 * radius * std::sqrt(50.0 / median)), 64.0, 2048.0) : 2048.0;
  return 2 * radius / n;
}

// Oracle verdicts on up to `samples` disagreeing pairs and `samples` pairs drawn at random (both among the compared
// pairs), with the uncovered fraction and pixel size of the pairs each backend gets wrong.
void judge(const std::string& only, int level, int samples) {
  std::printf("judge: exact oracle on sampled pairs, level %d, %d samples each\n", level, samples);
  for (const char* name : kAllParts) {
    if (!only.empty() && only != name) continue;
    const BackendMaps maps = backendMaps(name, level);
    const Mesh& mesh = maps.part.mesh;
    const std::vector<Vec3>& directions = maps.ray.directions.directions;
    std::vector<std::pair<int, int>> differ, all;
    for (int t = 0; t < mesh.triangleCount(); ++t) {
      const Vec3 n = triangleNormal(mesh, t);
      for (int d = 0; d < static_cast<int>(directions.size()); ++d) {
        if (!compared(n, directions[d])) continue;
        all.emplace_back(t, d);
        if (maps.ray.map.bits.get(t, d) != maps.render.map.bits.get(t, d)) differ.emplace_back(t, d);
      }
    }
    auto sample = [samples](std::vector<std::pair<int, int>>& pairs) {
      std::mt19937 rng(12345);
      std::shuffle(pairs.begin(), pairs.end(), rng);
      if (static_cast<int>(pairs.size()) > samples) pairs.resize(samples);
    };
    const double differ_fraction = double(differ.size()) / std::max<std::size_t>(all.size(), 1);
    sample(differ);
    sample(all);
    const std::vector<ExactPair> on_differ = exactVisibility(mesh, directions, differ);
    const std::vector<ExactPair> on_all = exactVisibility(mesh, directions, all);
    const double pixel = renderPixel(mesh);
    std::printf("  %s: %d tri, %zu dir, disagreement %.5f, pixel %.4f mm\n", name, mesh.triangleCount(),
                directions.size(), differ_fraction, pixel);
    // Per kind of disagreement: which backend says visible, who is right, and the typical shapes.
    struct Tally {
      int count = 0;
      std::vector<double> uncovered, pixels, width;
    };
    Tally tallies[2][2];  // [ray says visible][oracle agrees with ray]
    for (std::size_t i = 0; i < differ.size(); ++i) {
      const auto [t, d] = differ[i];
      const bool ray = maps.ray.map.bits.get(t, d), exact = on_differ[i].visible;
      Tally& tally = tallies[ray][exact == ray];
      ++tally.count;
      tally.uncovered.push_back(on_differ[i].uncovered);
      const auto [area, width] = projectedPixels(mesh, t, directions[d], pixel);
      tally.pixels.push_back(area);
      tally.width.push_back(width);
    }
    auto median = [](std::vector<double> v) {
      if (v.empty()) return 0.0;
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    for (int ray = 1; ray >= 0; --ray)
      for (int right = 1; right >= 0; --right) {
        const Tally& tally = tallies[ray][right];
        if (tally.count == 0) continue;
        std::printf("    %-13s says visible, %-6s right: %5d of %zu sampled  median uncovered %.2e, projected %.2f px, "
                    "width %.2f px\n", ray ? "ray" : "render", right ? "ray" : "render", tally.count, differ.size(),
                    median(tally.uncovered), median(tally.pixels), median(tally.width));
      }
    // Where the visible part the ray backend misses lies: by the witness's barycentric weights.
    int near_corner = 0, near_edge = 0, inside = 0;
    for (std::size_t i = 0; i < differ.size(); ++i) {
      const auto [t, d] = differ[i];
      if (maps.ray.map.bits.get(t, d) || !on_differ[i].visible) continue;
      const Vec3 a = mesh.corner(t, 0), e1 = mesh.corner(t, 1) - a, e2 = mesh.corner(t, 2) - a;
      const Vec3 n = e1.cross(e2), q = on_differ[i].witness - a;
      const double w1 = q.cross(e2).dot(n) / n.squaredNorm(), w2 = e1.cross(q).dot(n) / n.squaredNorm();
      const double w[3] = {1 - w1 - w2, w1, w2};
      if (std::max({w[0], w[1], w[2]}) > 0.85)
        ++near_corner;
      else if (std::min({w[0], w[1], w[2]}) < 0.05)
        ++near_edge;
      else
        ++inside;
    }
    std::printf("    ray misses: witness near a corner %d, near an edge %d, inside %d\n", near_corner, near_edge,
                inside);
    int ray_wrong = 0, render_wrong = 0, both_miss = 0;
    std::vector<double> missed;  // uncovered fraction of the pairs both backends call hidden and the oracle visible
    for (std::size_t i = 0; i < all.size(); ++i) {
      const bool ray = maps.ray.map.bits.get(all[i].first, all[i].second);
      const bool render = maps.render.map.bits.get(all[i].first, all[i].second);
      ray_wrong += ray != on_all[i].visible;
      render_wrong += render != on_all[i].visible;
      if (!ray && !render && on_all[i].visible) ++both_miss, missed.push_back(on_all[i].uncovered);
    }
    std::printf("    random pairs: ray wrong %.5f, render wrong %.5f (of %zu); both miss %d, median uncovered %.2e\n",
                double(ray_wrong) / all.size(), double(render_wrong) / all.size(), all.size(), both_miss,
                median(missed));
  }
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {});
  const std::vector<std::string>& p = positionalAtMost(a, 4);
  const std::string what = p.size() > 0 ? p[0] : "all";
  // The arguments after the figure's name: how many it takes, then each checked before any work starts.
  const std::map<std::string, std::size_t> takes{{"speed", 1}, {"scaling", 0}, {"accuracy", 2}, {"judge", 3}, {"all", 2}};
  if (!takes.count(what)) throw UsageError("unknown figure '" + what + "'");
  positionalAtMost(a, 1 + takes.at(what));
  const std::string variant = what == "speed" && p.size() > 1 ? p[1] : "";
  if (!variant.empty() && variant != "default" && variant != "ray")
    throw UsageError("speed takes default or ray, not '" + variant + "'");
  const std::string part = what != "speed" && p.size() > 1 ? p[1] : "";
  if (!part.empty()) requireOneOf(part, kAllParts);
  const int level = p.size() > 2 ? atLeast(parseInteger(p[2], "LEVEL"), 0, "LEVEL") : 4;
  const int samples = p.size() > 3 ? atLeast(parseInteger(p[3], "SAMPLES"), 1, "SAMPLES") : 2000;
  if (what == "speed" || what == "all") speed(variant);
  if (what == "scaling" || what == "all") scaling();
  if (what == "accuracy" || what == "all") accuracy(part, level);
  if (what == "judge") judge(part, level, samples);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // figures appear as they are measured, also into a file
  return runBench(argc, argv, kUsage, benchMain);
}
