// The poses a move is swept through (sweep.h: the sub-step bound and the directions that cost none).
#include <algorithm>
#include <cmath>

#include "art2part/simulation/sweep.h"

namespace art2part {

namespace {

double farthestCorner(const Box& box, const Vec3& p) {
  double far = 0;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c(i & 1 ? box.max.x() : box.min.x(), i & 2 ? box.max.y() : box.min.y(), i & 4 ? box.max.z() : box.min.z());
    far = std::max(far, (c - p).norm());
  }
  return far;
}

Vec3 slerp(const Vec3& a, const Vec3& b, double angle, double f) {
  if (angle < 1e-9) return ((1 - f) * a + f * b).normalized();
  Vec3 across = b - a.dot(b) * a;  // in the plane of a and b, perpendicular to a
  if (across.norm() < 1e-12) across = a.unitOrthogonal();  // opposite axes: any plane
  across.normalize();
  return (std::cos(f * angle) * a + std::sin(f * angle) * across).normalized();
}

int subSteps(double travel, double step) { return std::max(1, static_cast<int>(std::ceil(travel / step - 1e-9))); }

// Sub-steps for a motion split into a part the pose covers exactly (`free`: along the tool axis for a rise, along the
// rays for a slide) and the rest (`paced`). A pose stands for its whole sub-step by holding the paced part at its end
// while the free part runs over the sub-step, which puts the tool up to |paced| |free| / (n |motion|) off the line
// of the move at the start of the sub-step: n grows until that is at most `deviation`, so the sweep never cuts more
// than `deviation` beyond the true one (and the paced part alone is held to `step` between poses).
int stepsWithFreePart(double paced, double free, double step, double deviation) {
  const double motion = std::hypot(paced, free);
  int n = subSteps(paced, step);
  if (motion > 0.0 && paced * free / (n * motion) > deviation)
    n = std::max(n, subSteps(paced * free / motion, deviation));
  return n;
}

// The axis does not turn: the motion along the axis (rise) or along the rays (slide) is free, whichever saves more.
std::vector<SweepPose> translationPoses(const ToolPose& from, const ToolPose& to, double step, double deviation,
                                        int axis) {
  const Vec3& a = to.axis;
  const Vec3 motion = to.tip - from.tip;
  const double axial = motion.dot(a);
  Vec3 across_rays = motion;
  across_rays[axis] = 0.0;
  const int rising = stepsWithFreePart((motion - axial * a).norm(), std::abs(axial), step, deviation);
  const int sliding = stepsWithFreePart(across_rays.norm(), std::abs(motion[axis]), step, deviation);
  const bool slide = std::abs(a[axis]) < 1.0 - 1e-12 && sliding < rising;
  const int count = slide ? sliding : rising;
  std::vector<SweepPose> poses(count);
  for (int s = 1; s <= count; ++s) {
    const Vec3 tip = from.tip + (static_cast<double>(s) / count) * motion;
    if (slide) {
      poses[s - 1] = {{tip, a}, 0.0, motion[axis] / count};
    } else {
      const double rise = axial / count;
      poses[s - 1] = {{tip - std::max(rise, 0.0) * a, a}, std::abs(rise), 0.0};
    }
  }
  return poses;
}

bool continues(const Toolpath& path, std::size_t m) { return !toolPlacedAt(path, static_cast<int>(m)); }

// Whether move m + 1 carries on along the line of the run that starts with move `first`.
bool carriesOn(const Toolpath& path, std::size_t first, std::size_t m) {
  const CutterLocation &next = path[m + 1], &start = path[first];
  if (!continues(path, m + 1) || next.op != start.op || next.move != start.move || next.axis != start.axis)
    return false;
  const Vec3 along = start.tip - path[first - 1].tip, d = next.tip - path[m].tip;
  return d.dot(along) > 0.0 && d.cross(along).norm() <= 1e-9 * d.norm() * along.norm();
}

}  // namespace

bool toolPlacedAt(const Toolpath& path, int row) {
  return row == 0 || path[row - 1].tool != path[row].tool || path[row - 1].setup != path[row].setup;
}

std::vector<StraightRun> straightRuns(const Toolpath& path) {
  std::vector<StraightRun> runs;
  for (std::size_t m = 0; m < path.size();) {
    StraightRun run{static_cast<int>(m), static_cast<int>(m), !continues(path, m)};
    if (!run.placed && path[m - 1].axis == path[m].axis)
      while (static_cast<std::size_t>(run.last) + 1 < path.size() && carriesOn(path, m, run.last)) ++run.last;
    runs.push_back(run);
    m = run.last + 1;
  }
  return runs;
}

std::vector<SweepPose> movePoses(const ToolPose& from, const ToolPose& to, const ToolSolid& tool, const Box& stock_box,
                                 double step, double deviation, int axis) {
  const double angle = std::acos(std::clamp(from.axis.dot(to.axis), -1.0, 1.0));
  if (angle < 1e-9) return translationPoses(from, to, step, deviation, axis);
  const double reach = std::min(std::hypot(tool.length, tool.max_radius),
                                std::max(farthestCorner(stock_box, from.tip), farthestCorner(stock_box, to.tip)));
  const Vec3 motion = to.tip - from.tip;
  const int count = subSteps(motion.norm() + angle * reach, step);
  std::vector<SweepPose> poses(count);
  for (int s = 1; s <= count; ++s) {
    const double f = static_cast<double>(s) / count;
    poses[s - 1] = {{from.tip + f * motion, slerp(from.axis, to.axis, angle, f)}, 0.0, 0.0};
  }
  return poses;
}

}  // namespace art2part
