// 5-axis surface finishing with a ball (surface_finishing.h): centres from the passes planned along the face's
// direction, each point's axis leaning from the setup direction towards it only as far as the flutes, shank and
// holder need, the lean smoothed along the pass; links retract along the axis above the part.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "art2part/finishing/surface_finishing.h"
#include "art2part/roughing/shadow.h"
#include "axis_probe.h"
#include "surface_plan.h"

namespace art2part {

namespace surface {

namespace {

// mm: the flutes' cylinder above the ball's centre may come this close to the part (it touches the contact's
// neighbourhood tangentially where the ball meets a wall at its equator).
constexpr double kFluteClearance = 1e-3;
// Smoothing the tilt can raise it where a larger tilt collides: the search and the smoothing are repeated this often.
constexpr int kTiltRounds = 4;

struct Tilting {
  const AxisProbe& probe;
  const Tool& tool;
  std::vector<Zone> body;  // shank and holder against the part grown by skin + holder margin
  Vec3 z, w;               // the setup direction, and the unit direction it leans towards (in their plane)
  double max_tilt = 0;     // rad
  double step = 0;         // rad
  double R = 0;

  Vec3 axis(double tilt) const { return std::cos(tilt) * z + std::sin(tilt) * w; }

  // The ball at `centre` with axis a: its flutes clear the part, its shank and holder the grown part, all continued
  // up the axis (so the retract along it is clear too). `hints`: one per zone, the flutes' first.
  bool clear(const Vec3& centre, const Vec3& a, std::vector<ProbeHint>& hints) const {
    hints.resize(body.size() + 1);
    const Vec3 tip = centre - R * a;
    if (probe.any(tip, a, R - kFluteClearance, R, hints[0])) return false;
    for (std::size_t k = 0; k < body.size(); ++k)
      if (probe.any(tip, a, body[k].radius + body[k].grow, body[k].height - body[k].grow, hints[k + 1])) return false;
    return true;
  }

  // The least tilt, from `from` up in steps (max_tilt the last), at which the ball at `centre` clears; -1: none.
  double leastTilt(const Vec3& centre, double from, std::vector<ProbeHint>& hints) const {
    for (double t = from;; t += step) {
      const double tilt = std::min(t, max_tilt);
      if (clear(centre, axis(tilt), hints)) return tilt;
      if (tilt >= max_tilt) return -1;
    }
  }
};

struct Pose {
  Vec3 tip, axis;
};

// One pass's centres given tilts: each stretch of points that clear, its poses. Tilts are the least clear ones,
// raised so they change at most `rate` rad per mm along the pass, checked again where the raise made them collide.
std::vector<std::vector<Pose>> tiltPass(const Tilting& tilting, const std::vector<Vec3>& centres, double rate,
                                        int& skipped) {
  const std::size_t n = centres.size();
  std::vector<ProbeHint> hints;
  std::vector<double> s(n, 0), tilt(n, -1), need(n, 0);
  for (std::size_t i = 1; i < n; ++i) s[i] = s[i - 1] + (centres[i] - centres[i - 1]).norm();
  for (std::size_t i = 0; i < n; ++i) need[i] = tilting.leastTilt(centres[i], 0, hints);
  for (int round = 0; round < kTiltRounds; ++round) {
    // Raise each tilt to what its neighbours need less the rate times the distance (forward, then backward).
    for (std::size_t i = 0; i < n; ++i) tilt[i] = need[i];
    for (std::size_t i = 1; i < n; ++i)
      if (tilt[i] >= 0 && tilt[i - 1] >= 0) tilt[i] = std::max(tilt[i], tilt[i - 1] - rate * (s[i] - s[i - 1]));
    for (std::size_t i = n - 1; i-- > 0;)
      if (tilt[i] >= 0 && tilt[i + 1] >= 0) tilt[i] = std::max(tilt[i], tilt[i + 1] - rate * (s[i + 1] - s[i]));
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (tilt[i] < 0 || tilt[i] == need[i] || tilting.clear(centres[i], tilting.axis(tilt[i]), hints)) continue;
      need[i] = tilting.leastTilt(centres[i], tilt[i], hints);
      changed = true;
    }
    if (!changed) break;
  }
  std::vector<std::vector<Pose>> out(1);
  for (std::size_t i = 0; i < n; ++i) {
    // A tilt the search found is clear already; one the smoothing raised was checked in its last round only if
    // that round changed nothing after it.
    const bool ok = tilt[i] >= 0 && (tilt[i] == need[i] || tilting.clear(centres[i], tilting.axis(tilt[i]), hints));
    if (!ok) {
      ++skipped;
      if (!out.back().empty()) out.emplace_back();
      continue;
    }
    const Vec3 a = tilting.axis(tilt[i]);
    out.back().push_back(Pose{centres[i] - tilting.R * a, a});
  }
  out.erase(std::remove_if(out.begin(), out.end(), [](const std::vector<Pose>& p) { return p.size() < 2; }), out.end());
  return out;
}

// The lowest any point of the tool comes below its tip, along z, when its axis leans by `tilt`.
double dropBelowTip(const Tool& tool, double tilt) {
  double lowest = 0;
  const double length = toolLength(tool);
  for (int k = 0; k <= 1000; ++k) {
    const double h = length * k / 1000;
    lowest = std::min(lowest, h * std::cos(tilt) - toolRadiusAt(tool, h) * std::sin(tilt));
  }
  return -lowest;
}

}  // namespace

}  // namespace surface

SurfaceFinishingResult finishSurfaces5Axis(const Part& part, const std::vector<int>& faces, const SetupFrame& frame,
                                           const Vec3& face_direction, const Tool& tool, int setup,
                                           const SurfaceFinishingOptions& options) {
  using namespace surface;
  const auto start = std::chrono::steady_clock::now();
  checkTool(tool);
  if (tool.type != ToolType::Ball)
    throw InputError("5-axis surface finishing: tool '" + tool.id + "' is not a ball end mill");
  if (!(face_direction.norm() > 0) || !face_direction.allFinite())
    throw InputError("5-axis surface finishing: the face direction must be a non-zero vector");
  const Vec3 d = face_direction.normalized();
  // The drop frame: z along the face's direction.
  SetupFrame drop_frame;
  drop_frame.origin = frame.origin;
  drop_frame.z = d;
  drop_frame.x = d.unitOrthogonal();
  drop_frame.y = d.cross(drop_frame.x);
  SurfaceFinishingResult result;
  Plan plan = planPasses(part, faces, drop_frame, tool, options, false, {}, result);
  const double R = 0.5 * tool.diameter;

  const AxisProbe probe(part.mesh);
  Tilting tilting{probe, tool, bodyZones(tool, options.skin + options.holder_margin), frame.z, Vec3::Zero()};
  const Vec3 lean = d - d.dot(frame.z) * frame.z;
  tilting.R = R;
  tilting.step = options.tilt_step_deg * M_PI / 180;
  if (lean.norm() > 1e-9) {
    tilting.w = lean.normalized();
    tilting.max_tilt = std::min(options.max_tilt_deg * M_PI / 180, std::acos(std::clamp(d.dot(frame.z), -1.0, 1.0)));
  } else {
    tilting.w = frame.x;  // the face's direction is the setup's: no lean
  }
  const double rate = options.max_tilt_rate_deg_mm * M_PI / 180;

  // The tilted passes.
  std::vector<std::vector<Pose>> passes;
  if (plan.ctx) {
    const std::vector<Pass>& planned = plan.ordered.passes;
    std::vector<std::vector<std::vector<Pose>>> tilted(planned.size());
    std::vector<int> skipped(planned.size(), 0);
    // The passes' chords are straight along the CL surface, but the tool turning along a long one sweeps its body
    // through poses no check saw: centres are taken at most a sample step apart, each pose checked.
    const double step = plan.ctx->sample_step;
    parallelFor(static_cast<int>(planned.size()), options.threads, [&](int k) {
      std::vector<Vec3> centres;
      for (const Vec3& p : planned[k].points) {
        const Vec3 c = fromFrame(p, drop_frame) + R * d;
        if (!centres.empty()) {
          const Vec3 from = centres.back();
          const int pieces = static_cast<int>(std::ceil((c - from).norm() / step));
          for (int m = 1; m < pieces; ++m) centres.push_back(from + (c - from) * (static_cast<double>(m) / pieces));
        }
        centres.push_back(c);
      }
      tilted[k] = tiltPass(tilting, centres, rate, skipped[k]);
    });
    for (auto& t : tilted)
      for (auto& poses : t) passes.push_back(std::move(poses));
    // The planner's belief: a planned triangle is skipped when no tilt clears the ball touching its centroid.
    std::vector<char> blocked(plan.planned.size(), 0);
    parallelFor(static_cast<int>(plan.planned.size()), options.threads, [&](int k) {
      const int t = plan.planned[k];
      const Vec3 n = triangleNormal(part.mesh, t);
      std::vector<ProbeHint> hints;
      blocked[k] = tilting.leastTilt(triangleCentroid(part.mesh, t) + R * n, 0, hints) < 0;
    });
    for (std::size_t k = 0; k < plan.planned.size(); ++k)
      if (blocked[k]) {
        const double area = triangleArea(part.mesh, plan.planned[k]);
        result.skipped_area_mm2 += area;
        result.planned_area_mm2 -= area;
      }
  }

  // Links: lift along the axis at feed until the tool clears the part grown by the skin, then along the axis to the
  // traverse height (where no point of the tool, leaning at most max_tilt, comes within `clearance` of the part's
  // top), over to the next pass's axis line, and down it.
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : part.mesh.vertices) top = std::max(top, (v - frame.origin).dot(frame.z));
  const double traverse = top + options.clearance + dropBelowTip(tool, tilting.max_tilt);
  auto height = [&](const Vec3& p) { return (p - frame.origin).dot(frame.z); };
  auto lift = [&](const Pose& p) {
    const double h = probe.highest(p.tip, p.axis, R + options.skin, -std::numeric_limits<double>::infinity());
    return std::max(0.0, h + options.skin) + options.link_margin;
  };
  auto push = [&](const Vec3& tip, const Vec3& axis, MoveKind kind) {
    result.path.push_back(cutterLocation(setup, tool.id, kind, tip, axis));
  };
  for (const std::vector<Pose>& poses : passes) {
    const Pose& first = poses.front();
    const double up = (traverse - height(first.tip)) / first.axis.dot(frame.z);
    const double out = std::min(up, lift(first));
    push(first.tip + up * first.axis, first.axis, MoveKind::Rapid);
    push(first.tip + out * first.axis, first.axis, MoveKind::Rapid);
    for (const Pose& p : poses) push(p.tip, p.axis, MoveKind::Feed);
    const Pose& last = poses.back();
    const double up_last = (traverse - height(last.tip)) / last.axis.dot(frame.z);
    push(last.tip + std::min(up_last, lift(last)) * last.axis, last.axis, MoveKind::Feed);
    push(last.tip + up_last * last.axis, last.axis, MoveKind::Rapid);
    ++result.retracts;
  }
  result.drops = plan.ctx ? plan.ctx->drops.load() : 0;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace art2part
