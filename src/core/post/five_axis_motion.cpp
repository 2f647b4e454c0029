// Continuous 5-axis setups: inverse kinematics per point (inverseKinematicsPath: each point from the one before, so C
// unwinds without jumping a turn, and singular poses take the C of the next regular pose), then each CL segment
// subdivided by bisection until the linearly interpolated joints keep the tip within the chordal tolerance of the
// straight segment and the tool axis within the axis tolerance of the interpolated (slerp) axis, checked at 7 points
// of every piece. A segment into (or out of) a singular pose whose C differs on its two sides is followed with C held,
// then C turns in place at the singular pose: a pass that reaches the vertical in one plane and leaves it in another
// posts without a lift.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "program_builder.h"

namespace art2part::post_detail {

namespace {

constexpr int kMaxDepth = 24;       // bisections of one CL segment: pieces of 2^-24 of it
constexpr int kChecksPerPiece = 8;  // interior checks at 1/8 .. 7/8

JointPosition interpolated(const JointPosition& a, const JointPosition& b, double f) {
  JointPosition joints;
  joints.linear = a.linear + f * (b.linear - a.linear);
  joints.tilt = a.tilt + f * (b.tilt - a.tilt);
  joints.rotary = a.rotary + f * (b.rotary - a.rotary);
  return joints;
}

// Great-circle interpolation of two unit axes (a straight blend when they nearly coincide).
Vec3 slerp(const Vec3& a, const Vec3& b, double f) {
  const double angle = angleBetween(a, b);
  if (angle < 1e-9) return (a + f * (b - a)).normalized();
  const double s = std::sin(angle);
  return (std::sin((1 - f) * angle) / s * a + std::sin(f * angle) / s * b).normalized();
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double f = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + f * ab)).norm();
}

// One CL segment: its end poses and the setup's placement with the segment's tool.
struct ClSegment {
  const Machine& machine;
  const Placement& placement;
  ToolPose from, to;
  const PostOptions& options;

  ToolPose at(double s) const {
    ToolPose pose;
    pose.tip = from.tip + s * (to.tip - from.tip);
    pose.axis = slerp(from.axis, to.axis, s);
    return pose;
  }

  // Do the joints interpolated linearly from ja (at s = sa) to jb (at sb) follow the segment?
  bool followedBy(const JointPosition& ja, double sa, const JointPosition& jb, double sb) const {
    for (int k = 1; k < kChecksPerPiece; ++k) {
      const double f = static_cast<double>(k) / kChecksPerPiece;
      const ToolPose pose = forwardKinematics(machine, placement, interpolated(ja, jb, f));
      if (distanceToSegment(pose.tip, from.tip, to.tip) > options.chordal_tolerance) return false;
      if (angleBetween(pose.axis, at(sa + f * (sb - sa)).axis) > options.axis_tolerance_deg * kDegree) return false;
    }
    return true;
  }
};

struct SubPoint {
  JointPosition joints;
  double s = 0;  // along the CL segment, 0..1
};

// Appends the joints after ja up to jb (inclusive) that the segment needs between sa and sb; false when the joints
// cannot follow it (an IK failure or a jump that does not shrink: the pose needs the other branch).
bool refine(const ClSegment& segment, const JointPosition& ja, double sa, const JointPosition& jb, double sb,
            int depth, std::vector<SubPoint>& out) {
  if (segment.followedBy(ja, sa, jb, sb)) {
    out.push_back({jb, sb});
    return true;
  }
  if (depth >= kMaxDepth) return false;
  const double sm = 0.5 * (sa + sb);
  const IkSolution middle =
      inverseKinematics(segment.machine, segment.placement, segment.at(sm), ja, segment.options.ik);
  if (!middle.ok()) return false;
  return refine(segment, ja, sa, middle.joints, sm, depth + 1, out) &&
         refine(segment, middle.joints, sm, jb, sb, depth + 1, out);
}

// The joints that hold the pose of a singular point with C at `rotary` (the pose's tilt; C free there).
JointPosition heldAt(const ClSegment& segment, const ToolPose& pose, const JointPosition& near, double rotary) {
  JointPosition previous = near;
  previous.rotary = rotary;
  return inverseKinematics(segment.machine, segment.placement, pose, previous, segment.options.ik).joints;
}

// A turn of C in place at a singular pose (tip and axis held, only C and the linear joints moving): bisected until the
// linearly interpolated joints keep the tip within the chordal tolerance of the point. Appends the joints after ja up
// to jb (inclusive) at `s`.
bool turnInPlace(const ClSegment& turn, const JointPosition& ja, const JointPosition& jb, double s, int depth,
                 std::vector<SubPoint>& out) {
  if (turn.followedBy(ja, s, jb, s)) {
    out.push_back({jb, s});
    return true;
  }
  if (depth >= kMaxDepth) return false;
  const JointPosition middle = heldAt(turn, turn.from, ja, 0.5 * (ja.rotary + jb.rotary));
  return turnInPlace(turn, ja, middle, s, depth + 1, out) && turnInPlace(turn, middle, jb, s, depth + 1, out);
}

// The joints along a CL segment whose end (or start) is singular and whose C differs across it: the tilt follows the
// segment with C held, and C turns in place at the singular end (or first, at the singular start).
bool followWithTurn(const ClSegment& segment, const IkSolution& from, const IkSolution& to,
                    std::vector<SubPoint>& out) {
  if (to.rotary_held) {
    const JointPosition held = heldAt(segment, segment.to, to.joints, from.joints.rotary);
    const ClSegment turn{segment.machine, segment.placement, segment.to, segment.to, segment.options};
    return refine(segment, from.joints, 0.0, held, 1.0, 0, out) && turnInPlace(turn, held, to.joints, 1.0, 0, out);
  }
  if (from.rotary_held) {
    const JointPosition turned = heldAt(segment, segment.from, from.joints, to.joints.rotary);
    const ClSegment turn{segment.machine, segment.placement, segment.from, segment.from, segment.options};
    return turnInPlace(turn, from.joints, turned, 0.0, 0, out) && refine(segment, turned, 0.0, to.joints, 1.0, 0, out);
  }
  return false;
}

std::string describeJump(const Machine& machine, const JointPosition& a, const JointPosition& b) {
  char text[200];
  std::snprintf(text, sizeof text, "%s %.3f -> %.3f deg, %s %.3f -> %.3f deg", machine.tiltJoint().name.c_str(),
                a.tilt / kDegree, b.tilt / kDegree, machine.rotaryJoint().name.c_str(), a.rotary / kDegree,
                b.rotary / kDegree);
  return text;
}

// The IK chain of one tool run, every point reached (else an error naming the point).
std::vector<IkSolution> solveRun(const ProgramBuilder& builder, PointRun run, const Placement& placement) {
  std::vector<ToolPose> poses;
  for (int row = run.begin; row < run.end; ++row) poses.push_back(poseOf(builder.path()[row]));
  std::vector<IkSolution> solutions =
      inverseKinematicsPath(builder.machine(), placement, poses, builder.current(), builder.options().ik);
  for (int i = 0; i < static_cast<int>(solutions.size()); ++i)
    if (!solutions[i].ok())
      throw InputError(describePoint(builder.path(), run.begin + i) + ": machine " + builder.machine().name +
                       " cannot reach this tool pose: " + solutions[i].reason);
  return solutions;
}

// The moves from point row - 1 to point row; false when the joints cannot follow the segment.
bool segmentMoves(ProgramBuilder& builder, const Placement& placement, int row, const IkSolution& from,
                  const IkSolution& to) {
  const Toolpath& path = builder.path();
  const ClSegment segment{builder.machine(), placement, poseOf(path[row - 1]), poseOf(path[row]), builder.options()};
  std::vector<SubPoint> points;
  if (!refine(segment, from.joints, 0.0, to.joints, 1.0, 0, points)) {
    points.clear();
    if (!followWithTurn(segment, from, to, points)) return false;
  }
  const MoveKind move = path[row].move;
  const double feed = move == MoveKind::Feed ? builder.feedFor(row - 1, row) : 0.0;
  const double length = (path[row].tip - path[row - 1].tip).norm();
  double s = 0;
  for (const SubPoint& point : points) {
    ProgramStep step;
    step.move = move;
    step.joints = point.joints;
    step.feed_mm_min = feed;
    step.tip_length = (point.s - s) * length;
    step.row = row;
    step.at_row = point.s == 1.0;
    s = point.s;
    builder.moveTo(step);
  }
  return true;
}

}  // namespace

void planFiveAxis(ProgramBuilder& builder, PointRun setup_run) {
  const Toolpath& path = builder.path();
  for (const PointRun& run : toolRuns(path, setup_run)) {
    const Placement placement = builder.placementFor(run.begin);
    const std::vector<IkSolution> solutions = solveRun(builder, run, placement);
    builder.retract();
    builder.changeTool(builder.toolOf(run.begin).number);
    builder.note("op " + std::to_string(path[run.begin].op));
    builder.approach(solutions[0].joints, path[run.begin].move, run.begin);
    for (int row = run.begin + 1; row < run.end; ++row) {
      const IkSolution& from = solutions[row - 1 - run.begin];
      const IkSolution& to = solutions[row - run.begin];
      if (path[row].op != path[row - 1].op) builder.note("op " + std::to_string(path[row].op));
      if (segmentMoves(builder, placement, row, from, to)) continue;
      if (path[row].move == MoveKind::Feed)
        throw InputError(describePoint(path, row) + ": the joints cannot follow this feed move continuously from "
                         "the point before (" + describeJump(builder.machine(), from.joints, to.joints) +
                         "): the pose needs the other IK branch or leaves the travel mid-move; lift the tool there");
      builder.note("reposition: the rapid needs the other IK branch");
      builder.approach(to.joints, MoveKind::Rapid, row);
    }
  }
}

}  // namespace art2part::post_detail
