// Roughing the simulation finds useless, left out (useless_operations.h).
#include "art2part/plan/useless_operations.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace art2part {

namespace {

// The leftover may differ from the sum by float rounding of the lattice's volumes only.
constexpr double kVolumeSlack = 1e-9;

double roughingRemoved(const PlanResult& plan) {
  double removed = 0;
  for (const PlanOperation& op : plan.operations) {
    const auto check = plan.verification.by_op.find(op.index);
    if (!op.finishing && check != plan.verification.by_op.end()) removed += check->second.swept.removed_mm3;
  }
  return removed;
}

// What the verification found operation source (of plan.roughing.operations) removing.
double removedBy(const PlanResult& plan, int source) {
  for (const PlanOperation& op : plan.operations) {
    if (op.finishing || op.source != source) continue;
    const auto check = plan.verification.by_op.find(op.index);
    return check == plan.verification.by_op.end() ? 0.0 : check->second.swept.removed_mm3;
  }
  return 0;
}

std::string format(const char* pattern, double a, double b, double c) {
  char text[240];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

DroppedOperation droppedBySimulation(const RoughingOperation& op, double removed, double roughing_removed) {
  DroppedOperation d = droppedOperation(
      op, format("the simulation found it removing %.0f mm3, %.3f%% of the %.0f mm3 the roughing removes: left out, "
                 "the plan verified again without it",
                 removed, 100 * removed / roughing_removed, roughing_removed));
  d.simulated = true;
  d.removed_mm3 = removed;
  d.seconds = op.seconds;
  return d;
}

// Why the plan without the useless operations is not kept, or empty when it is.
std::string notAsClean(const VerificationReport& before, const VerificationReport& after, double dropped_removed) {
  if (after.cancelled) return "the verification without them was cancelled";
  if (after.gouges > before.gouges)
    return "without them the simulation finds " + std::to_string(after.gouges) + " gouges (" +
           std::to_string(before.gouges) + " with them)";
  if (after.collisions > before.collisions)
    return "without them the simulation finds " + std::to_string(after.collisions) + " collisions (" +
           std::to_string(before.collisions) + " with them)";
  const double allowed = before.leftover_volume_mm3 + dropped_removed;
  if (after.leftover_volume_mm3 > allowed + kVolumeSlack * std::max(1.0, before.stock_volume_mm3))
    return format("without them the simulation leaves %.0f mm3 (%.0f mm3 with them, %.0f mm3 more allowed)",
                  after.leftover_volume_mm3, before.leftover_volume_mm3, dropped_removed);
  return "";
}

}  // namespace

std::vector<int> uselessRoughing(const PlanResult& plan) {
  std::vector<int> useless;
  if (!plan.verified) return useless;
  const double roughing_removed = roughingRemoved(plan);
  if (roughing_removed <= 0) return useless;
  for (const PlanOperation& op : plan.operations) {
    if (op.finishing) continue;
    if (removedBy(plan, op.source) < kUselessRemovalShare * roughing_removed) useless.push_back(op.source);
  }
  std::sort(useless.begin(), useless.end());
  return useless;
}

void dropUselessRoughing(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options,
                         const PlanVerifier& verify) {
  plan.useless = UselessRoughing{};
  const std::vector<int> useless = uselessRoughing(plan);
  plan.useless.found = static_cast<int>(useless.size());
  if (useless.empty()) return;

  const double roughing_removed = roughingRemoved(plan);
  std::vector<DroppedOperation> dropped;
  double dropped_removed = 0;
  for (int source : useless) {
    const double removed = removedBy(plan, source);
    dropped_removed += removed;
    dropped.push_back(droppedBySimulation(plan.roughing.operations[source], removed, roughing_removed));
  }
  // Out of the roughing, last first so the indices hold; back in first first.
  std::vector<RoughingOperation> held(useless.size());
  for (std::size_t i = useless.size(); i-- > 0;) {
    held[i] = std::move(plan.roughing.operations[useless[i]]);
    plan.roughing.operations.erase(plan.roughing.operations.begin() + useless[i]);
  }
  combinePlan(plan, part, library, options);
  VerificationState state;
  VerificationReport without = verify(plan, state);

  plan.useless.kept_why = notAsClean(plan.verification, without, dropped_removed);
  if (plan.useless.kept_why.empty()) {
    plan.useless.dropped = true;
    plan.verification = std::move(without);
    plan.simulation = std::move(state);
    for (DroppedOperation& d : dropped) plan.roughing.dropped.push_back(std::move(d));
    return;
  }
  plan.cancelled = plan.cancelled || without.cancelled;
  for (std::size_t i = 0; i < useless.size(); ++i)
    plan.roughing.operations.insert(plan.roughing.operations.begin() + useless[i], std::move(held[i]));
  combinePlan(plan, part, library, options);
}

}  // namespace art2part
