// The joint trajectory evaluated: positions, velocities and accelerations at any time, fixed-rate samples, the CSV;
// and the waypoints of a post program.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>

#include "art2part/tooling/toolpath.h"  // appendFixed
#include "art2part/post/joint_trajectory.h"

namespace art2part {

namespace {

constexpr double kRadToDeg = 180 / 3.14159265358979323846;

std::vector<double> toStd(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

}  // namespace

std::vector<JointWaypoint> programWaypoints(const MachineProgram& program) {
  std::vector<JointWaypoint> waypoints;
  JointWaypoint start;
  start.joints = program.start;
  start.stop = true;
  waypoints.push_back(start);
  double tool_length = 0;
  for (const SetupProgram& setup : program.setups) {
    for (const ProgramStep& step : setup.steps) {
      if (step.kind == StepKind::ToolChange) {
        waypoints.back().stop = true;
        tool_length = program.tool(step.tool).length;
        continue;
      }
      JointWaypoint waypoint;
      waypoint.joints = step.joints;
      waypoint.move = step.kind == StepKind::Retract ? MoveKind::Rapid : step.move;
      waypoint.feed_mm_min = step.feed_mm_min;
      waypoint.tool_length = tool_length;
      waypoints.push_back(waypoint);
    }
    waypoints.back().stop = true;  // M0 between setups, M30 at the end
  }
  return waypoints;
}

JointTrajectory::JointTrajectory(const Machine& machine, std::vector<JointWaypoint> waypoints,
                                 std::vector<TrajectorySegment> segments, std::vector<double> corner_beta,
                                 std::vector<TrajectoryPiece> pieces)
    : waypoints_(std::move(waypoints)), segments_(std::move(segments)), corner_beta_(std::move(corner_beta)),
      pieces_(std::move(pieces)) {
  for (const Joint& joint : machine.joints) {
    joint_names_.push_back(joint.name);
    rotary_.push_back(joint.rotary);
  }
  first_ = Eigen::Map<const Eigen::VectorXd>(jointVector(machine, waypoints_.front().joints).data(),
                                             machine.jointCount());
}

double JointTrajectory::duration() const {
  return pieces_.empty() ? 0.0 : pieces_.back().start + pieces_.back().duration;
}

const TrajectoryPiece* JointTrajectory::pieceAt(double t, double& tau) const {
  if (pieces_.empty()) return nullptr;
  t = std::clamp(t, 0.0, duration());
  auto after = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                                [](double time, const TrajectoryPiece& piece) { return time < piece.start; });
  const TrajectoryPiece& piece = after == pieces_.begin() ? pieces_.front() : *(after - 1);
  tau = std::clamp(t - piece.start, 0.0, piece.duration);
  return &piece;
}

std::vector<double> JointTrajectory::derivativeAt(double t, int order) const {
  double tau = 0;
  const TrajectoryPiece* piece = pieceAt(t, tau);
  if (!piece) return order == 0 ? toStd(first_) : std::vector<double>(first_.size(), 0.0);
  if (piece->blend) {  // a parabola in joint space from the segment before into this one
    const int k = piece->segment;
    const Eigen::VectorXd& before = segments_[k - 1].direction;
    const Eigen::VectorXd turn = (segments_[k].direction - before) / (2 * corner_beta_[k]);
    if (order == 0)
      return toStd(segments_[k].start + (piece->s0 + piece->sigma0 * tau) * before + turn * (0.5 * tau * tau));
    if (order == 1) return toStd(piece->sigma0 * before + turn * tau);
    return toStd(turn);
  }
  const TrajectorySegment& segment = segments_[piece->segment];
  const double s = piece->s0 + piece->sigma0 * tau + 0.5 * piece->sigma_dot * tau * tau;
  if (order == 0) return toStd(segment.start + s * segment.direction);
  if (order == 1) return toStd((piece->sigma0 + piece->sigma_dot * tau) * segment.direction);
  return toStd(piece->sigma_dot * segment.direction);
}

std::vector<double> JointTrajectory::positionAt(double t) const { return derivativeAt(t, 0); }
std::vector<double> JointTrajectory::velocityAt(double t) const { return derivativeAt(t, 1); }
std::vector<double> JointTrajectory::accelerationAt(double t) const { return derivativeAt(t, 2); }

PathPoint JointTrajectory::pathPointAt(double t) const {
  double tau = 0;
  const TrajectoryPiece* piece = pieceAt(t, tau);
  if (!piece) return {};
  if (piece->blend) {
    const int k = piece->segment;
    const double s = piece->s0 + piece->sigma0 * tau;
    if (s < 0) return {k - 1, (segments_[k - 1].length + s) / segments_[k - 1].length};
    return {k, s / segments_[k].length};
  }
  const double s = piece->s0 + piece->sigma0 * tau + 0.5 * piece->sigma_dot * tau * tau;
  return {piece->segment, s / segments_[piece->segment].length};
}

std::vector<double> JointTrajectory::pathPosition(const PathPoint& point) const {
  if (segments_.empty()) return toStd(first_);
  const TrajectorySegment& segment = segments_.at(point.segment);
  return toStd(segment.start + (point.fraction * segment.length) * segment.direction);
}

std::vector<TrajectorySample> sampleTrajectory(const JointTrajectory& trajectory, double rate_hz) {
  if (!(rate_hz > 0)) throw InputError("trajectory: the sample rate must be positive");
  const double duration = trajectory.duration();
  const long count = static_cast<long>(std::floor(duration * rate_hz + 1e-9));
  std::vector<TrajectorySample> samples;
  samples.reserve(count + 2);
  for (long k = 0; k <= count; ++k) {
    const double t = k / rate_hz;
    samples.push_back({t, trajectory.positionAt(t)});
  }
  if (duration - count / rate_hz > 1e-9) samples.push_back({duration, trajectory.positionAt(duration)});
  return samples;
}

void writeTrajectoryCsv(const JointTrajectory& trajectory, double rate_hz, const std::string& path) {
  std::ofstream file(path, std::ios::binary);
  if (!file) throw InputError("cannot write " + path);
  std::string out = "time";
  for (const std::string& name : trajectory.jointNames()) out += "," + name;
  out += "\n";
  for (const TrajectorySample& sample : sampleTrajectory(trajectory, rate_hz)) {
    appendFixed(out, sample.time, 6);
    for (size_t j = 0; j < sample.joints.size(); ++j) {
      out += ',';
      appendFixed(out, trajectory.rotary()[j] ? sample.joints[j] * kRadToDeg : sample.joints[j], 6);
    }
    out += '\n';
    if (out.size() > (1 << 20)) {
      file << out;
      out.clear();
    }
  }
  file << out;
  if (!file) throw InputError("cannot write " + path);
}

}  // namespace art2part
