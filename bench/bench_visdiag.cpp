// Temporary diagnostic: categorise ray/render disagreements by projected size and dense-grid escape fraction.
#include <embree3/rtcore.h>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <algorithm>
#include "art2part/geometry/part.h"
#include "art2part/visibility/analysis.h"
using namespace art2part;
int main(int argc, char** argv) {
  const std::string name = argv[1];
  const int level = argc > 2 ? std::stoi(argv[2]) : 2;
  const Part part = loadPart(std::string(ART2PART_SHARED_PARTS) + "/" + name);
  const Mesh& m = part.mesh;
  VisibilityOptions o; o.level = level; o.side_correction = false;
  const VisibilityResult ray = analyseVisibility(part, o);
  o.backend = VisibilityBackend::Render;
  const VisibilityResult ren = analyseVisibility(part, o);
  const Box box = boundingBox(m); const Vec3 c = box.center();
  double R = 0; for (auto& v : m.vertices) R = std::max(R, (v - c).norm()); R *= 1.001;
  std::vector<double> areas; for (int t = 0; t < m.triangleCount(); ++t) areas.push_back(triangleArea(m, t));
  std::nth_element(areas.begin(), areas.begin() + areas.size() / 2, areas.end());
  int N = std::clamp((int)std::ceil(2 * R * std::sqrt(50 / areas[areas.size() / 2])), 64, 2048);
  const double pix = 2 * R / N;
  RTCDevice dev = rtcNewDevice(nullptr); RTCScene sc = rtcNewScene(dev);
  rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vb = (float*)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.vertices.size());
  unsigned* ib = (unsigned*)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, m.triangles.size());
  for (size_t i = 0; i < m.vertices.size(); ++i) for (int k = 0; k < 3; ++k) vb[3 * i + k] = float(m.vertices[i][k] - c[k]);
  for (size_t i = 0; i < m.triangles.size(); ++i) for (int k = 0; k < 3; ++k) ib[3 * i + k] = m.triangles[i][k];
  rtcCommitGeometry(g); rtcAttachGeometry(sc, g); rtcReleaseGeometry(g); rtcCommitScene(sc);
  const double lift = 1e-6 * box.diagonal();
  auto escapeFraction = [&](int t, const Vec3& d) {
    const Vec3 a = m.corner(t, 0) - c, b = m.corner(t, 1) - c, cc = m.corner(t, 2) - c, n = triangleNormal(m, t);
    int esc = 0, tot = 0; const int G = 12;
    for (int i = 0; i <= G; ++i) for (int j = 0; i + j <= G; ++j) {
      double u = (i + 0.02) / (G + 0.06), v = (j + 0.02) / (G + 0.06), w = 1 - u - v;
      Vec3 p = w * a + u * b + v * cc + lift * n;
      RTCIntersectContext ctx; rtcInitIntersectContext(&ctx);
      RTCRay r; r.org_x = p.x(); r.org_y = p.y(); r.org_z = p.z(); r.tnear = 0; r.dir_x = d.x(); r.dir_y = d.y(); r.dir_z = d.z();
      r.time = 0; r.tfar = std::numeric_limits<float>::infinity(); r.mask = ~0u; r.id = 0; r.flags = 0;
      rtcOccluded1(sc, &ctx, &r); esc += r.tfar >= 0; ++tot;
    }
    return double(esc) / tot;
  };
  const double grazing = std::sin(2.0 * M_PI / 180);
  // [kind][sizebin][occl: 0 none escaped,1 partly,2 all]
  long long cnt[2][5][3] = {}; long long compared = 0;
  const double sizes[4] = {0.25, 1, 4, 30};
  for (int t = 0; t < m.triangleCount(); ++t) {
    const Vec3 n = triangleNormal(m, t);
    for (int d = 0; d < ray.map.directions(); ++d) {
      const Vec3 dir = ray.directions.directions[d];
      const double nd = n.dot(dir);
      if (std::abs(nd) < grazing) continue;
      ++compared;
      const bool a = ray.map.bits.get(t, d), b = ren.map.bits.get(t, d);
      if (a == b) continue;
      const double px = triangleArea(m, t) * nd / (pix * pix);
      int sb = 0; while (sb < 4 && px > sizes[sb]) ++sb;
      const double f = escapeFraction(t, dir.normalized());
      cnt[a ? 0 : 1][sb][f == 0 ? 0 : f == 1 ? 2 : 1]++;
    }
  }
  std::printf("%s level %d: N=%d compared %lld\n", name.c_str(), level, N, compared);
  const char* bins[5] = {"<0.25px", "<1px", "<4px", "<30px", ">=30px"};
  for (int k = 0; k < 2; ++k) {
    std::printf(k == 0 ? "ray-only (render missed)\n" : "render-only (ray missed)\n");
    for (int s = 0; s < 5; ++s) std::printf("  %-8s  grid hidden %6lld  partly %6lld  all %6lld\n", bins[s], cnt[k][s][0], cnt[k][s][1], cnt[k][s][2]);
  }
  rtcReleaseScene(sc); rtcReleaseDevice(dev);
}
