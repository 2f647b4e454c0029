// Rays for the render backend's sub-pixel cases (render_fallback.h), on the ray backend's scene (ray_scene.h).
#include "render_fallback.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "ray_scene.h"

namespace art2part::idrender {

namespace {

using raycast::Float3;
using raycast::Prepared;

// Triangles thinner than this many pixels in a view (twice the projected area over the longest projected side) may
// win no pixel centre: they get rays from every interior sample. 1.5 px: the outline, drawn 0.75 px inside, collapses
// to a point below that.
constexpr double kThinPixels = 1.5;

// Where along a shared edge the spreading rays start (fractions from its first corner): the middle and both ends,
// since a piece peeking out from under an occluder most often sits in a corner.
constexpr double kEdgeSamples[] = {0.5, 0.12, 0.88, 0.03, 0.97};

// Rounds of spreading from newly found triangles to their neighbours (a visible strip can cross many slivers).
constexpr int kRounds = 24;

constexpr std::size_t kBlock = 1024;  // rays traced at a time

}  // namespace

struct RayFallback::Shared {
  Shared(const Mesh& mesh, double pixel_size)
      : prepared(raycast::prepare(mesh, raycast::kMaxSamples)), scene(prepared), pixel(pixel_size) {}
  Prepared prepared;
  raycast::EmbreeScene scene;
  double pixel;
};

RayFallback::RayFallback(const Mesh& mesh, double pixel) : shared_(std::make_unique<Shared>(mesh, pixel)) {}
RayFallback::~RayFallback() = default;

struct RayFallback::Tracer::State {
  explicit State(const Shared& s) : shared(s), p(s.prepared), seen(p.size(), -1) {}

  // Positions of the triangles shown, then those found: a ray settles a triangle once.
  void complete(const Vec3& d, std::vector<int>& visible) {
    ++stamp;
    found.clear();
    for (int t : visible) {
      seen[p.position[t]] = stamp;
      found.push_back(p.position[t]);
    }
    thinPass(d);
    std::size_t fresh = 0;  // found[fresh..]: not yet spread from
    for (int round = 0; round < kRounds && fresh < found.size(); ++round) {
      const std::size_t end = found.size();
      edgePass(d, fresh, end);
      fresh = end;
    }
    for (std::size_t k = visible.size(); k < found.size(); ++k) visible.push_back(p.triangle[found[k]]);
  }

  bool facing(int i, const Vec3& d) const { return p.nx[i] * d.x() + p.ny[i] * d.y() + p.nz[i] * d.z() > 0.0; }

  // Every front-facing triangle no pixel showed and too thin to be sure of: rays from all its interior samples.
  void thinPass(const Vec3& d) {
    const double limit = kThinPixels * shared.pixel;
    for (int i = 0; i < p.size(); ++i) {
      if (seen[i] == stamp || !facing(i, d)) continue;
      const raycast::WalkTriangle& w = p.walk[i];
      const Vec3 a(w.corner[0][0], w.corner[0][1], w.corner[0][2]);
      const Vec3 e1 = Vec3(w.corner[1][0], w.corner[1][1], w.corner[1][2]) - a;
      const Vec3 e2 = Vec3(w.corner[2][0], w.corner[2][1], w.corner[2][2]) - a;
      const Vec3 e3 = e2 - e1;
      auto across = [&d](const Vec3& e) { return (e - e.dot(d) * d).squaredNorm(); };
      const double longest = std::sqrt(std::max({across(e1), across(e2), across(e3)}));
      if (std::abs(e1.cross(e2).dot(d)) >= limit * longest) continue;  // wide enough for the pixels
      if (rays.size() + p.samples > kBlock) trace();
      for (int s = 0; s < p.samples; ++s) add(p.origins[s][i], d, i);
    }
    trace();
  }

  // Hidden front-facing neighbours of found[begin, end): rays from just inside the shared edge.
  void edgePass(const Vec3& d, std::size_t begin, std::size_t end) {
    edges.clear();
    for (std::size_t v = begin; v < end; ++v) {
      const int j = found[v];
      for (int i : p.walk[j].across) {
        if (i < 0 || seen[i] == stamp || !facing(i, d)) continue;
        for (int k = 0; k < 3; ++k)
          if (p.walk[i].across[k] == j) edges.push_back(i << 2 | k);
      }
    }
    std::sort(edges.begin(), edges.end());  // neighbouring rays start side by side
    for (int e : edges) {
      const int i = e >> 2, k = e & 3;
      if (seen[i] == stamp) continue;
      if (rays.size() + std::size(kEdgeSamples) > kBlock) trace();
      for (double along : kEdgeSamples) add(raycast::edgeSample(p, i, k, along), d, i);
    }
    trace();
  }

  void add(const Float3& origin, const Vec3& d, int owner) {
    rays.push_back(raycast::occlusionRay(origin, d, 0));
    owners.push_back(owner);
  }

  // Traces the rays gathered; each owner with a ray that escaped is found (once).
  void trace() {
    if (!rays.empty()) {
      raycast::TraceContext context;  // no occluders recorded: rays = 0
      rtcInitIntersectContext(&context.base);
      context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      rtcOccluded1M(shared.scene.scene(), &context.base, rays.data(), static_cast<unsigned>(rays.size()),
                    sizeof(RTCRay));
      for (std::size_t r = 0; r < rays.size(); ++r)
        if (rays[r].tfar >= 0.0f && seen[owners[r]] != stamp) {
          seen[owners[r]] = stamp;
          found.push_back(owners[r]);
        }
    }
    rays.clear();
    owners.clear();
  }

  const Shared& shared;
  const Prepared& p;
  std::vector<int> seen;  // by position: stamped when shown or found in this view
  std::vector<int> found, edges, owners;
  std::vector<RTCRay> rays;
  int stamp = 0;
};

RayFallback::Tracer::Tracer(const RayFallback& fallback) : state_(std::make_unique<State>(*fallback.shared_)) {}
RayFallback::Tracer::~Tracer() = default;

void RayFallback::Tracer::complete(const Vec3& d, std::vector<int>& visible) { state_->complete(d, visible); }

}  // namespace art2part::idrender
