// A plan's cycle time and each operation's removal against its bound (plan_figures.h).
#include "art2part/plan/plan_figures.h"

#include <algorithm>
#include <cstdio>

#include "art2part/plan/useless_operations.h"

namespace art2part {

namespace {

// Per setup: the part frame turned into the machine's axes, the setup frame along the table's (fixtureFacingUp).
std::map<int, Eigen::Matrix3d> setupRotations(const SetupPlan& setups) {
  std::map<int, Eigen::Matrix3d> rotations;
  for (int k = 0; k < static_cast<int>(setups.setups.size()); ++k) {
    const SetupFrame& f = setups.setups[k].frame;
    Eigen::Matrix3d r;
    r.row(0) = f.x.transpose();
    r.row(1) = f.y.transpose();
    r.row(2) = f.z.transpose();
    rotations[k] = r;
  }
  return rotations;
}

const Tool* findTool(const std::vector<Tool>& tools, const std::string& id) {
  for (const Tool& t : tools)
    if (t.id == id) return &t;
  return nullptr;
}

std::string uselessReason(double removed, double roughing_removed) {
  char text[200];
  std::snprintf(text, sizeof text, "removes %.0f mm3, %.2f%% of the %.0f mm3 the roughing removes (under %.2g%%)",
                removed, 100 * removed / roughing_removed, roughing_removed, 100 * kUselessRemovalShare);
  return text;
}

}  // namespace

PlanFigures planFigures(const PlanResult& plan, const Machine& machine) {
  PlanFigures figures;
  figures.limits = motionLimits(machine);
  figures.machine = machine.joints.empty() ? "default" : machine.name;
  figures.time = cycleTime(plan.toolpath, plan.tools, figures.limits, setupRotations(plan.setups));
  for (const PlanOperation& op : plan.operations) {
    OperationFigures f;
    f.index = op.index;
    f.finishing = op.finishing;
    const auto time = figures.time.by_op.find(op.index);
    if (time != figures.time.by_op.end()) f.time = time->second;
    (op.finishing ? figures.finishing : figures.roughing) += f.time;
    if (plan.verified) {
      f.simulated = true;
      const auto checked = plan.verification.by_op.find(op.index);
      if (checked != plan.verification.by_op.end()) {
        f.removed_mm3 = checked->second.swept.removed_mm3;
        f.axial_depth_mm = levelCutDepth(checked->second.swept, kAxialDepthShare);
        f.deepest_level_cut_mm = checked->second.swept.deepest_level_cut_mm;
        f.gouges = checked->second.gouges;
        f.collisions = checked->second.collisions;
        f.rapid_collisions = checked->second.rapid_collisions;
        f.worst_collision_mm = checked->second.worst_collision_mm;
      }
      if (f.time.motion_s() > 0) f.mm3_per_min = f.removed_mm3 / (f.time.motion_s() / 60);
      const Tool* tool = findTool(plan.tools, op.tool);
      const double rate = tool ? libraryRemovalRate(*tool) : 0.0;
      if (rate > 0) f.bound_s = 60 * f.removed_mm3 / rate;
      if (f.bound_s >= kLeastBoundSeconds) f.bound_ratio = f.time.total_s() / f.bound_s;
      if (!op.finishing) {
        figures.roughing_removed_mm3 += f.removed_mm3;
        figures.roughing_bound_s += f.bound_s;
      }
    }
    figures.operations.push_back(f);
  }
  const std::vector<int> useless = uselessRoughing(plan);  // sorted sources, the rule dropUselessRoughing applies
  for (std::size_t i = 0; i < plan.operations.size(); ++i) {
    const PlanOperation& op = plan.operations[i];
    if (op.finishing || !std::binary_search(useless.begin(), useless.end(), op.source)) continue;
    OperationFigures& f = figures.operations[i];
    f.useless = true;
    f.useless_reason = uselessReason(f.removed_mm3, figures.roughing_removed_mm3);
  }
  return figures;
}

}  // namespace art2part
