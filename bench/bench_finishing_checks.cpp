// The measures that judge a finished part (issue 17, "Figures to reach"): surface coverage (surface_coverage.h) and
// scallops on local windows (scallop_probe.h), on synthetic finishing paths, with their speed.
//   bench_finishing_checks ctc01 [--threads N]
//       CTC-01 (STEP): a face-milling raster over the top of its box (10 mm flat, stepover 7 mm, tip on the top), then
//       a dome (hemisphere of radius 30 mm, 0.5 deg facets) under a 3-axis raster of a 6 mm ball at stepover 0.49 mm
//       (0.01 mm cusp on the flat), its heights exact on the sphere: coverage per surface type, scallops on 400
//       windows at pitch stepover / 20, seconds.
//   bench_finishing_checks raster PART [--stepover S] [--threads N]
//       a 6 mm ball rastered over the whole part from +z (heights dropped on the part's z dexels at 0.5 mm, a point every
//       0.5 mm): the coverage's speed at the size of a real finishing path (CTC-02's mesh: about 10^7 poses).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include "art2part/geometry/part.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/scallop_probe.h"
#include "art2part/simulation/stock.h"
#include "art2part/simulation/surface_coverage.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_finishing_checks ctc01 [--threads N]\n"
    "       bench_finishing_checks raster PART [--stepover S] [--threads N]   (PART a path)\n";
constexpr double kPi = 3.14159265358979323846;
constexpr double kDropResolution = 0.5;  // mm: the height map's lattice (CTC-02 at 0.1 mm would be 60 M rays)

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Tool endMill(const std::string& id, ToolType type, double diameter) {
  Tool t;
  t.id = id;
  t.type = type;
  t.diameter = diameter;
  t.corner_radius = type == ToolType::Ball ? diameter / 2 : 0;
  t.flute_length = 3 * diameter;
  t.shank_diameter = diameter;
  t.stickout = 5 * diameter;
  t.holder = {{32, 40}};
  return t;
}

CutterLocation at(const Tool& tool, MoveKind move, const Vec3& tip) {
  CutterLocation c;
  c.tool = tool.id;
  c.move = move;
  c.tip = tip;
  return c;
}

// Lines along x at `stepover` across the box's y (one tool radius beyond each side), zig-zag, a point every `spacing`
// at the height `z(x, y)`, from a rapid above.
template <class Height>
Toolpath raster(const Tool& tool, const Box& box, double stepover, double spacing, Height z) {
  const double r = 0.5 * tool.diameter;
  const double x0 = box.min.x() - r, x1 = box.max.x() + r, y0 = box.min.y() - r, y1 = box.max.y() + r;
  const int lines = static_cast<int>(std::ceil((y1 - y0) / stepover)) + 1;
  const int points = std::max(2, static_cast<int>(std::ceil((x1 - x0) / spacing)) + 1);
  Toolpath path{at(tool, MoveKind::Rapid, Vec3(x0, y0, box.max.z() + 20))};
  for (int line = 0; line < lines; ++line) {
    const double y = y0 + line * stepover;
    for (int k = 0; k < points; ++k) {
      const double f = static_cast<double>(line % 2 ? points - 1 - k : k) / (points - 1);
      const double x = x0 + f * (x1 - x0);
      path.push_back(at(tool, MoveKind::Feed, Vec3(x, y, z(x, y))));
    }
  }
  path.push_back(at(tool, MoveKind::Rapid, path.back().tip + Vec3(0, 0, 20)));
  return path;
}

// A hemisphere of radius `radius` on z = 0 (its base disc closing it), facets of `step_deg`. Faces: 0 the cap within
// `cap_deg` of the pole, 1 the rest of the sphere, 2 the base.
Mesh dome(double radius, double step_deg, double cap_deg, std::vector<int>& triangle_face) {
  Mesh m;
  const int rings = static_cast<int>(std::round(90 / step_deg)), sectors = static_cast<int>(std::round(360 / step_deg));
  m.vertices.emplace_back(0, 0, radius);  // the pole
  for (int i = 1; i <= rings; ++i) {
    const double polar = 0.5 * kPi * i / rings;
    for (int j = 0; j < sectors; ++j) {
      const double azimuth = 2 * kPi * j / sectors;
      m.vertices.emplace_back(radius * std::sin(polar) * std::cos(azimuth), radius * std::sin(polar) * std::sin(azimuth),
                              radius * std::cos(polar));
    }
  }
  auto ring = [&](int i, int j) { return 1 + (i - 1) * sectors + (j % sectors); };
  const int cap_rings = static_cast<int>(std::round(cap_deg / step_deg));
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  triangle_face.assign(sectors, 0);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
      triangle_face.insert(triangle_face.end(), 2, i < cap_rings ? 0 : 1);
    }
  const int centre = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, 0);
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({centre, ring(rings, j + 1), ring(rings, j)});
  triangle_face.insert(triangle_face.end(), sectors, 2);
  return m;
}

// CPU seconds of the process since `start` (the machine is shared: wall time alone says little).
double cpuSince(std::clock_t start) { return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC; }

void printCoverage(const char* what, const CoverageReport& r, double cpu) {
  std::printf("%s: %.2f %% of %.0f mm2 covered; %ld samples at %.3f mm, %lld poses, %lld distance queries, %.2f s "
              "wall, %.2f s CPU (%.2f M poses per CPU second)\n",
              what, 100 * r.share(), r.area_mm2, r.samples, r.sample_spacing_mm, r.poses, r.pose_queries, r.seconds,
              cpu, 1e-6 * r.poses / std::max(cpu, 1e-9));
  for (const TypeCoverage& t : r.types)
    std::printf("    %-9s %6.2f %% of %8.0f mm2\n", surfaceTypeName(t.type), 100 * t.share(), t.area_mm2);
}

int ctc01(int threads) {
  const std::string file = std::string(ART2PART_SHARED_PARTS) + "/nist_ctc_01_asme1_rd.stp";
  auto start = std::chrono::steady_clock::now();
  const Part part = loadPart(file);
  std::printf("part: %s, %d triangles, %zu faces, loaded in %.2f s\n", file.c_str(), part.mesh.triangleCount(),
              part.faces.size(), since(start));
  const Box box = boundingBox(part.mesh);
  const Tool flat = endMill("flat10", ToolType::Flat, 10);
  const Toolpath face_mill = raster(flat, box, 7.0, 1000.0, [&](double, double) { return box.max.z(); });
  CoverageOptions coverage;
  coverage.threads = threads;
  std::clock_t cpu = std::clock();
  const CoverageReport top = surfaceCoverage(part.mesh, part.triangle_face, part.faces, face_mill, {flat}, coverage);
  printCoverage("CTC-01, face milling its top (flat10, stepover 7)", top, cpuSince(cpu));
  int top_faces = 0;
  for (const FaceCoverage& f : top.faces)
    if (f.covered_samples > 0 && f.share() > 0.999) ++top_faces;
  std::printf("    faces wholly covered: %d\n", top_faces);

  const double radius = 30, R = 3, stepover = 0.49;
  std::vector<int> dome_faces;
  const Mesh hemisphere = dome(radius, 0.5, 45, dome_faces);
  const Tool ball = endMill("ball6", ToolType::Ball, 2 * R);
  Box over;  // the raster stays on the dome up to 50 deg of slope (the base's edge would need a drop-cutter)
  over.extend(Vec3(-radius * std::sin(50 * kPi / 180), -radius * std::sin(50 * kPi / 180), 0));
  over.extend(Vec3(radius * std::sin(50 * kPi / 180), radius * std::sin(50 * kPi / 180), radius));
  const double reach = radius * std::sin(50 * kPi / 180) + 0.5 * R;
  // The ball's tip over the sphere: its centre radius + R from the dome's centre.
  auto tip = [&](double x, double y) {
    const double rho2 = std::min(x * x + y * y, reach * reach);
    return std::sqrt((radius + R) * (radius + R) - rho2) - R;
  };
  Toolpath ball_raster = raster(ball, over, stepover, 0.5, tip);
  std::printf("dome: %d triangles; ball raster %zu points over the cap within 50 deg of the pole\n",
              hemisphere.triangleCount(), ball_raster.size());
  std::vector<Face> faces(3);
  faces[0].type = faces[1].type = SurfaceType::Sphere;
  faces[2].type = SurfaceType::Plane;
  cpu = std::clock();
  const CoverageReport dome_coverage = surfaceCoverage(hemisphere, dome_faces, faces, ball_raster, {ball}, coverage);
  printCoverage("dome, ball raster (ball6, stepover 0.49)", dome_coverage, cpuSince(cpu));
  std::printf("    the cap within 45 deg of the pole: %.2f %% of %.0f mm2\n", 100 * dome_coverage.faces[0].share(),
              dome_coverage.faces[0].area_mm2);

  ScallopProbeOptions probe;
  probe.threads = threads;
  probe.half_width = stepover;
  probe.pitch = stepover / 20;
  probe.depth = 0.5;
  cpu = std::clock();
  const ScallopReport scallops = probeScallops(hemisphere, dome_faces, {0}, ball_raster, {ball}, probe);
  const double scallop_cpu = cpuSince(cpu);
  std::printf("dome scallops on the cap: %zu windows at pitch %.4f mm, %d fully reached; max quantiles 50 %% %.4f, 90 %% %.4f, "
              "99 %% %.4f, max %.4f mm; within 0.011 mm: %.1f %%; %lld ray-piece tests, %.2f s wall, %.2f s CPU\n",
              scallops.windows.size(), probe.pitch, scallops.fullyReachedCount(), scallops.quantile(0.5),
              scallops.quantile(0.9), scallops.quantile(0.99), scallops.quantile(1.0),
              100 * scallops.shareWithin(0.011), scallops.ray_piece_tests, scallops.seconds, scallop_cpu);
  // Windows near the pole (slope under 10 deg) against the flat's cusp, the steepest ones against 1 / cos^2.
  double pole_max = 0;
  int pole = 0;
  for (const ScallopWindow& w : scallops.windows)
    if (w.fullyReached() && w.normal.z() > std::cos(10 * kPi / 180)) {
      pole_max = std::max(pole_max, w.max_mm);
      ++pole;
    }
  // On a sphere of radius rho the 3-axis raster's passes, s apart across, lie w = s rho / (rho + R) apart on the
  // surface near the pole: the cusp (w^2 / 8)(1/R + 1/rho), plus the facets' sagitta.
  const double w = stepover * radius / (radius + R), convex = w * w / 8 * (1 / R + 1 / radius);
  std::printf("    %d windows within 10 deg of the pole: max %.4f mm (convex cusp (w^2/8)(1/R + 1/rho) = %.4f, facets' "
              "sagitta %.4f)\n",
              pole, pole_max, convex, radius * (1 - std::cos(0.25 * kPi / 180)));
  return 0;
}

// The ball's lowest tip over a height map of the part's tops (z dexels).
class BallDrop {
 public:
  BallDrop(const Mesh& mesh, double radius, double resolution)
      : lattice_(DexelLattice::over(stockBox(boundingBox(mesh), radius + 1), resolution)),
        dexels_(mesh, lattice_), radius_(radius) {}

  double drop(double x, double y, double floor) const {
    const auto is = lattice_.indexRange(0, x - radius_, x + radius_), js = lattice_.indexRange(1, y - radius_, y + radius_);
    double z = floor;
    for (int j = js[0]; j <= js[1]; ++j)
      for (int i = is[0]; i <= is[1]; ++i) {
        const double dx = lattice_.coordinate(0, i) - x, dy = lattice_.coordinate(1, j) - y, d2 = dx * dx + dy * dy;
        if (d2 > radius_ * radius_) continue;
        const int ray = lattice_.rayIndex(2, i, j);
        if (dexels_.begin(2, ray) == dexels_.end(2, ray)) continue;
        z = std::max(z, (dexels_.end(2, ray) - 1)->hi + std::sqrt(radius_ * radius_ - d2) - radius_);
      }
    return z;
  }

 private:
  DexelLattice lattice_;
  MeshDexels dexels_;
  double radius_;
};

int wholeRaster(const std::string& file, double stepover, int threads) {
  auto start = std::chrono::steady_clock::now();
  const Part part = loadPart(file);
  std::printf("part: %s, %d triangles, %zu faces, loaded in %.2f s\n", file.c_str(), part.mesh.triangleCount(),
              part.faces.size(), since(start));
  const Box box = boundingBox(part.mesh);
  const Tool ball = endMill("ball6", ToolType::Ball, 6);
  start = std::chrono::steady_clock::now();
  const BallDrop drop(part.mesh, 3.0, kDropResolution);
  const Toolpath path = raster(ball, box, stepover, 0.5, [&](double x, double y) { return drop.drop(x, y, box.min.z()); });
  std::printf("path: ball6 raster from +z at stepover %.3f mm, %zu points, %.0f m of feed, made in %.1f s\n", stepover,
              path.size(), 1e-3 * toolpathLength(path, MoveKind::Feed), since(start));
  CoverageOptions coverage;
  coverage.threads = threads;
  const std::clock_t cpu = std::clock();
  const CoverageReport r = surfaceCoverage(part.mesh, part.triangle_face, part.faces, path, {ball}, coverage);
  printCoverage("coverage", r, cpuSince(cpu));
  return 0;
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {"threads", "stepover"});
  const std::vector<std::string>& p = positionalAtMost(a, 2);
  const int threads = atLeast(a.integer("threads", 0), 0, "--threads");
  const double stepover = positive(a.number("stepover", 0.49), "--stepover");
  const std::string mode = p.empty() ? "" : p[0];
  if (mode == "ctc01" && p.size() == 1) return ctc01(threads);
  if (mode == "raster" && p.size() == 2) {
    requireFile(p[1]);
    return wholeRaster(p[1], stepover, threads);
  }
  if (mode == "ctc01") throw UsageError("ctc01 takes no PART");
  if (mode == "raster") throw UsageError("raster needs a PART");
  throw UsageError(mode.empty() ? "ctc01 or raster expected" : "ctc01 or raster expected, not '" + mode + "'");
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
