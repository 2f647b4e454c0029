// Ray-casting visibility (thesis 3.2, the ray-tracing counterpart of the graphics approach of 3.2.1) with Embree 3.
//
// Triangle t is visible along d when n . d > 0 and at least one of its sample points has a clear ray to infinity
// along +d. Per direction: collect the front-facing triangles, then one pass per sample point in which every
// triangle still hidden shoots one occlusion ray from its next sample; those that escape are visible and drop out.
//
// Speed comes from coherence. All rays of a direction are parallel and, with the triangles in Morton order, start
// side by side, so Embree's coherent streams share most of their traversal. And occluders repeat: the surface that
// hid a triangle's centroid usually hides its other samples too. The occlusion filter records which triangle
// stopped each ray; the next sample's ray is first walked over the mesh from that triangle (ray_scene.h), and goes
// to Embree only when the walk finds no triangle it clearly passes through. A hit found by the walk is a real hit,
// so the answer is exactly the ray-casting one, only cheaper. (Remembering occluders from one direction to the next
// was tried too: the walks got long and cost more than the rays they saved.)
//
// A few interior samples miss a triangle that is only partly visible when its visible part holds none of them: a
// strip along the rim of a pocket, a face half under an overhang. The visible part of a triangle almost always
// touches one of its edges, and the neighbour across that edge is then usually visible too. So with refine_edges,
// triangles still hidden next to a visible neighbour shoot a few more rays from just inside the shared edge, round
// after round while that finds more (a visible strip can cross several thin triangles). The rays start at the middle
// and near both ends of the edge: the exact oracle (exact_visibility.h) showed most pieces missed sit in a corner.
//
// The default (defaultRayOptions()) is the centroid ray alone, then refinement: the oracle finds it as right as four
// samples with refinement, at about three quarters of the cost, since refinement along the edges finds what the
// corner samples did. What it could still lose for good, a triangle whose visible part no neighbour leads to, the
// rescue takes back: triangles seen along no direction get every sample and their edges' points along every
// direction.
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "art2part/common/parallel.h"
#include "art2part/visibility/visibility.h"
#include "ray_scene.h"

namespace art2part {

namespace {

using raycast::Float3;
using raycast::Prepared;

// Rays traced at a time: few enough to stay in the core's cache (48 kB), many enough for Embree's streams.
constexpr std::size_t kBlock = 1024;

// Edge refinement: where along a shared edge the extra rays start (fractions from its first corner), and how many
// rounds of spreading from newly visible triangles to their neighbours at most (a round costs only the edges beside
// the triangles the last one found, so the cap is generous: a visible strip can cross many thin triangles).
constexpr double kEdgeSamples[] = {0.5, 0.12, 0.88, 0.03, 0.97};
constexpr int kEdgeSampleCount = 5;
constexpr int kRefineRounds = 24;

// The id of a ray whose occluder is not worth recording: beyond every position, so the filter skips it.
constexpr int kNoOccluder = -1;

// Directions are meant to be unit; normalising keeps n . d and the rays honest if not. A unit direction is used as
// given: renormalising would move its last bits and flip the sign of n . d for faces it runs along.
Vec3 unit(const Vec3& d) {
  const double length = d.norm();
  if (std::abs(length - 1.0) < 1e-12) return d;
  return length > 0.0 ? Vec3(d / length) : Vec3::Zero();
}

// One thread's tracing state: buffers reused from direction to direction, and the occluder of each triangle
// position's last occluded ray (-1: none yet).
class Tracer {
 public:
  // subset: positions (ascending) to trace, every triangle when empty; samples: passes per direction. The rescue
  // (a subset) also tries the edges of each triangle still hidden that it shares with a front-facing triangle.
  Tracer(RTCScene scene, const Prepared& p, bool refine, const std::vector<int>& subset, int samples)
      : scene_(scene), p_(p), refine_(refine), subset_(subset), samples_(samples), occluder_(p.size(), -1),
        seen_(refine || !subset.empty() ? p.size() : 0, -1) {}

  // Positions of the triangles visible along unit direction d.
  const std::vector<int>& visibleAlong(const Vec3& d) {
    visible_.clear();
    pending_.clear();
    const double dx = d.x(), dy = d.y(), dz = d.z();
    auto facing = [&](int i) { return p_.nx[i] * dx + p_.ny[i] * dy + p_.nz[i] * dz > 0.0; };
    if (subset_.empty()) {
      for (int i = 0; i < p_.size(); ++i)
        if (facing(i)) pending_.push_back(i);
    } else {
      for (int i : subset_)
        if (facing(i)) pending_.push_back(i);
    }
    for (int s = 0; s < samples_ && !pending_.empty(); ++s) samplePass(s, d);
    if (refine_) refineEdges(d);
    if (!subset_.empty()) rescueEdgePass(d);
    return visible_;
  }

 private:
  // Rounds of edge samples for the hidden triangles beside visible ones, spreading outwards: each round tries only
  // the edges across from triangles the previous round (or the samples) found visible, since a ray that failed from
  // the same point would fail again. seen_ marks by position the triangles visible along this direction (stamped
  // with a per-direction number, so it never needs clearing).
  void refineEdges(const Vec3& d) {
    ++stamp_;
    for (int i : visible_) seen_[i] = stamp_;
    std::size_t fresh = 0;  // visible_[fresh..] became visible in the last round
    for (int round = 0; round < kRefineRounds && fresh < visible_.size(); ++round) {
      const std::size_t end = visible_.size();
      edgePass(d, fresh, end);
      fresh = end;
    }
  }

  // One round: rays from near every edge that a front-facing, still hidden triangle shares with visible_[begin, end),
  // in position order so that neighbouring rays start side by side.
  void edgePass(const Vec3& d, std::size_t begin, std::size_t end) {
    const double dx = d.x(), dy = d.y(), dz = d.z();
    edges_.clear();
    for (std::size_t v = begin; v < end; ++v) {
      const int j = visible_[v];
      for (int i : p_.walk[j].across) {
        if (i < 0 || seen_[i] == stamp_ || !(p_.nx[i] * dx + p_.ny[i] * dy + p_.nz[i] * dz > 0.0)) continue;
        for (int k = 0; k < 3; ++k)
          if (p_.walk[i].across[k] == j) edges_.push_back(i << 2 | k);
      }
    }
    std::sort(edges_.begin(), edges_.end());
    rays_.clear();
    owners_.clear();
    for (int e : edges_) {
      const int i = e >> 2, k = e & 3;
      if (seen_[i] == stamp_) continue;  // an earlier block of this round found it
      if (rays_.size() + kEdgeSampleCount > kBlock) traceEdgeRays();
      for (double along : kEdgeSamples) {
        addRay(raycast::edgeSample(p_, i, k, along), d, kNoOccluder);
        owners_.push_back(i);
      }
    }
    traceEdgeRays();
  }

  // The rescue's edge rays: from near each edge a triangle still hidden shares with a front-facing one, every edge
  // that refinement from a visible neighbour could try, whether or not the main passes found that neighbour.
  void rescueEdgePass(const Vec3& d) {
    ++stamp_;
    for (int i : visible_) seen_[i] = stamp_;
    rays_.clear();
    owners_.clear();
    for (int i : pending_)
      for (int k = 0; k < 3; ++k) {
        const int j = p_.walk[i].across[k];
        if (j < 0 || !(p_.nx[j] * d.x() + p_.ny[j] * d.y() + p_.nz[j] * d.z() > 0.0)) continue;
        if (rays_.size() + kEdgeSampleCount > kBlock) traceEdgeRays();
        for (double along : kEdgeSamples) {
          // These triangles are mostly deep inside: what hid their samples hides their edges, and a walk from it
          // settles the ray without Embree (a walk's hit is a real hit).
          const Float3 origin = raycast::edgeSample(p_, i, k, along);
          if (occluder_[i] >= 0 && raycast::walkToHit(p_, origin, d, occluder_[i]) >= 0) continue;
          addRay(origin, d, kNoOccluder);
          owners_.push_back(i);
        }
      }
    traceEdgeRays();
  }

  // Traces the edge rays gathered so far; each owner with a ray that escaped becomes visible (once).
  void traceEdgeRays() {
    trace();
    for (std::size_t r = 0; r < rays_.size(); ++r) {
      const int i = owners_[r];
      if (rays_[r].tfar >= 0.0f && seen_[i] != stamp_) {
        seen_[i] = stamp_;
        visible_.push_back(i);
      }
    }
    rays_.clear();
    owners_.clear();
  }

  // One ray per pending triangle from sample s. Afterwards pending_ holds those still hidden, in position order.
  void samplePass(int s, const Vec3& d) {
    hidden_.clear();
    for (std::size_t begin = 0; begin < pending_.size(); begin += kBlock)
      sampleBlock(s, d, begin, std::min(pending_.size(), begin + kBlock));
    pending_.swap(hidden_);
  }

  // A block of pending_ at a time, so that the rays stay in cache between being written and being traced.
  void sampleBlock(int s, const Vec3& d, std::size_t begin, std::size_t end) {
    const std::vector<Float3>& origins = p_.origins[s];
    rays_.clear();
    for (std::size_t k = begin; k < end; ++k) {
      const int i = pending_[k];
      // Pass 0 has no occluder from this direction yet; one from another direction is too far away to walk from.
      const int hit = s > 0 && occluder_[i] >= 0 ? raycast::walkToHit(p_, origins[i], d, occluder_[i]) : -1;
      walked_[k - begin] = hit >= 0;
      if (hit >= 0)
        occluder_[i] = hit;
      else
        addRay(origins[i], d, i);
    }
    trace();
    const RTCRay* ray = rays_.data();
    for (std::size_t k = begin; k < end; ++k) {
      const int i = pending_[k];
      if (walked_[k - begin])
        hidden_.push_back(i);
      else
        ((ray++)->tfar >= 0.0f ? visible_ : hidden_).push_back(i);  // occluded: tfar = -inf
    }
  }

  void addRay(const Float3& origin, const Vec3& d, int position) {
    // The id is where the filter records the occluder.
    rays_.push_back(raycast::occlusionRay(origin, d, static_cast<unsigned>(position)));
  }

  void trace() {
    if (rays_.empty()) return;
    raycast::TraceContext context;
    rtcInitIntersectContext(&context.base);
    context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    context.occluder = occluder_.data();
    context.rays = static_cast<unsigned>(occluder_.size());
    rtcOccluded1M(scene_, &context.base, rays_.data(), static_cast<unsigned>(rays_.size()), sizeof(RTCRay));
  }

  RTCScene scene_;
  const Prepared& p_;
  const bool refine_;
  const std::vector<int>& subset_;
  const int samples_;
  std::vector<int> occluder_;
  std::vector<int> pending_, hidden_, visible_;
  std::array<char, kBlock> walked_;  // whether the walk settled each triangle of the block
  std::vector<RTCRay> rays_;
  std::vector<int> seen_, owners_;  // edge refinement: visible stamps by position; the position of each edge ray
  std::vector<int> edges_;          // edge refinement: position << 2 | edge of each edge to try this round
  int stamp_ = 0;
};

// Hands directions to the tracing threads one at a time and merges their results. Bits of different directions
// share words of a row, so results are written under a lock (well under a millisecond per direction, against
// several of tracing). The calling thread reports progress (runTicking), so a callback never runs on a tracing
// thread.
class Job {
 public:
  Job(RTCScene scene, const Prepared& prepared, bool refine, const std::vector<int>& subset, int samples,
      const std::vector<Vec3>& directions, BitMatrix& bits)
      : scene_(scene), prepared_(prepared), refine_(refine), subset_(subset), samples_(samples),
        directions_(directions), bits_(bits) {}

  // Throws "cancelled" when the progress function says stop, and what a tracing thread threw.
  void run(int threads, const Progress& progress) {
    const double total = static_cast<double>(directions_.size());
    const bool stopped = runTicking(
        threads, [this](int, const std::atomic<bool>& stop) { work(stop); }, kReportSeconds,
        [&] { return !progress || progress(done_.load() / total); });
    if (stopped) throw std::runtime_error("cancelled");
  }

 private:
  static constexpr double kReportSeconds = 0.1;

  void work(const std::atomic<bool>& stop) {
    Tracer tracer(scene_, prepared_, refine_, subset_, samples_);
    for (int d = next_++; d < static_cast<int>(directions_.size()) && !stop.load(); d = next_++)
      record(d, tracer.visibleAlong(unit(directions_[d])));
  }

  void record(int d, const std::vector<int>& visible) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (int i : visible) bits_.set(prepared_.triangle[i], d);
    ++done_;
  }

  RTCScene scene_;
  const Prepared& prepared_;
  const bool refine_;
  const std::vector<int>& subset_;
  const int samples_;
  const std::vector<Vec3>& directions_;
  BitMatrix& bits_;
  std::atomic<int> next_{0}, done_{0};
  std::mutex mutex_;  // guards bits_
};

// Each thread holds a few arrays the size of the mesh, so a mistaken huge request is capped.
int threadCount(int requested, int directions) {
  constexpr int kMaxThreads = 64;
  const int threads = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(threads, 1, std::clamp(directions, 1, kMaxThreads));
}

}  // namespace

VisibilityMap rayVisibility(const Mesh& mesh, const std::vector<Vec3>& directions, const RayVisibilityOptions& options,
                            const Progress& progress) {
  VisibilityMap map{BitMatrix(mesh.triangleCount(), static_cast<int>(directions.size()))};
  if (progress && !progress(0.0)) throw std::runtime_error("cancelled");
  if (mesh.triangleCount() == 0 || directions.empty()) return map;

  // Out-of-range sample counts are clamped rather than refused: 1 is the thesis's one-id-per-triangle answer,
  // 7 is every sample point defined.
  const Prepared prepared = raycast::prepare(mesh, std::clamp(options.samples_per_triangle, 1, raycast::kMaxSamples));
  const raycast::EmbreeScene scene(prepared);
  const int threads = threadCount(options.threads, static_cast<int>(directions.size()));
  const std::vector<int> everything;
  Job(scene.scene(), prepared, options.refine_edges, everything, prepared.samples, directions, map.bits)
      .run(threads, progress);
  // Rescue: a triangle seen along no direction at all gets every sample point along every direction, and points near
  // its edges shared with front-facing triangles: every ray a 7-sample run with refinement could try for it. Few
  // triangles are unseen (pockets' hidden faces, slivers under a lip), so this costs little and keeps the single
  // sample of the main passes from losing a triangle for good.
  std::vector<int> unseen;
  for (int i = 0; i < prepared.size() && options.rescue_unseen; ++i)
    if (map.bits.rowCount(prepared.triangle[i]) == 0) unseen.push_back(i);
  if (!unseen.empty())
    Job(scene.scene(), prepared, false, unseen, raycast::kMaxSamples, directions, map.bits).run(threads, {});
  if (progress) progress(1.0);
  return map;
}

}  // namespace art2part
