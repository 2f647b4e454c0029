// Roughing the simulation finds useless, left out (useless_operations.h).
#include "art2part/plan/useless_operations.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <utility>

namespace art2part {

namespace {

// The leftover may differ from the sum by float rounding of the lattice's volumes only.
constexpr double kVolumeSlack = 1e-9;
// Verifications after the first without every useless operation: each puts some setups' back (dropUselessRoughing).
constexpr int kKeepRounds = 3;

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

// Why the plan without the useless operations (`them`, as the line names them) is not kept, or empty when it is.
std::string notAsClean(const VerificationReport& before, const VerificationReport& after, double dropped_removed,
                       const std::string& them = "them") {
  if (after.cancelled) return "the verification without " + them + " was cancelled";
  if (after.gouges > before.gouges)
    return "without " + them + " the simulation finds " + std::to_string(after.gouges) + " gouges (" +
           std::to_string(before.gouges) + " with them)";
  if (after.collisions > before.collisions)
    return "without " + them + " the simulation finds " + std::to_string(after.collisions) + " collisions (" +
           std::to_string(before.collisions) + " with them)";
  const double allowed = before.leftover_volume_mm3 + dropped_removed;
  if (after.leftover_volume_mm3 > allowed + kVolumeSlack * std::max(1.0, before.stock_volume_mm3))
    return "without " + them +
           format(" the simulation leaves %.0f mm3 (%.0f mm3 with them, %.0f mm3 more allowed)",
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

namespace {

// The setups where `report` (of the combined `plan`) finds a gouge or a collision.
std::set<int> setupsWithFindings(const PlanResult& plan, const VerificationReport& report) {
  std::set<int> setups;
  for (const PlanOperation& op : plan.operations) {
    const auto check = report.by_op.find(op.index);
    if (check != report.by_op.end() && (check->second.gouges > 0 || check->second.collisions > 0))
      setups.insert(op.setup);
  }
  return setups;
}

// Leaves `drop` (sorted sources) out of plan.roughing, recombines and verifies. The operations left out come back in
// order with putBack.
struct Trial {
  std::vector<int> drop;
  std::vector<RoughingOperation> held;
  VerificationReport report;
  VerificationState state;
};

void leaveOut(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options,
              const PlanVerifier& verify, Trial& trial) {
  trial.held.resize(trial.drop.size());
  for (std::size_t i = trial.drop.size(); i-- > 0;) {  // last first, so the indices hold
    trial.held[i] = std::move(plan.roughing.operations[trial.drop[i]]);
    plan.roughing.operations.erase(plan.roughing.operations.begin() + trial.drop[i]);
  }
  combinePlan(plan, part, library, options);
  trial.report = verify(plan, trial.state);
}

void putBack(PlanResult& plan, Trial& trial) {
  for (std::size_t i = 0; i < trial.drop.size(); ++i)  // first first
    plan.roughing.operations.insert(plan.roughing.operations.begin() + trial.drop[i], std::move(trial.held[i]));
}

// Keeps the plan without trial.drop (left out of the plan already): their lines, its verification and simulation.
void keep(PlanResult& plan, Trial& trial, const std::map<int, double>& removed, double roughing_removed) {
  plan.useless.dropped = true;
  for (std::size_t i = 0; i < trial.drop.size(); ++i)
    plan.roughing.dropped.push_back(droppedBySimulation(trial.held[i], removed.at(trial.drop[i]), roughing_removed));
  plan.verification = std::move(trial.report);
  plan.simulation = std::move(trial.state);
}

}  // namespace

void dropUselessRoughing(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options,
                         const PlanVerifier& verify) {
  plan.useless = UselessRoughing{};
  const std::vector<int> useless = uselessRoughing(plan);
  plan.useless.found = static_cast<int>(useless.size());
  if (useless.empty()) return;

  const double roughing_removed = roughingRemoved(plan);
  std::map<int, double> removed;  // by source
  std::map<int, int> setup;       // by source
  for (int source : useless) {
    removed[source] = removedBy(plan, source);
    setup[source] = plan.roughing.operations[source].setup;
  }
  auto removedByAll = [&](const std::vector<int>& sources) {
    double sum = 0;
    for (int source : sources) sum += removed[source];
    return sum;
  };
  Trial all{useless, {}, {}, {}};
  leaveOut(plan, part, library, options, verify, all);
  const std::string why = notAsClean(plan.verification, all.report, removedByAll(useless));
  if (why.empty()) return keep(plan, all, removed, roughing_removed);
  const std::string why_all = notAsClean(plan.verification, all.report, removedByAll(useless), "all of them");
  std::set<int> troubled = setupsWithFindings(plan, all.report);
  putBack(plan, all);
  // Later rounds: put the useless operations of setups with findings back, the earliest such setup first (setups are
  // cut in sequence: findings in a later setup may come from the stock an earlier one's drop left), the last round
  // every setup with findings.
  std::set<int> kept_setups;
  for (int round = 1; round <= kKeepRounds && !troubled.empty() && !all.report.cancelled; ++round) {
    if (round == kKeepRounds) kept_setups.insert(troubled.begin(), troubled.end());
    else kept_setups.insert(*troubled.begin());
    Trial some;
    for (int source : useless)
      if (!kept_setups.count(setup[source])) some.drop.push_back(source);
    if (some.drop.empty()) break;
    leaveOut(plan, part, library, options, verify, some);
    if (notAsClean(plan.verification, some.report, removedByAll(some.drop)).empty()) {
      std::string listed;
      for (int k : kept_setups) listed += (listed.empty() ? "" : ", ") + std::to_string(k);
      plan.useless.kept = static_cast<int>(useless.size() - some.drop.size());
      plan.useless.kept_why = "those of setups " + listed + " kept: " + why_all;
      return keep(plan, some, removed, roughing_removed);
    }
    if (some.report.cancelled) {
      all.report.cancelled = true;
    } else {
      for (int k : setupsWithFindings(plan, some.report))
        if (!kept_setups.count(k)) troubled.insert(k);
      for (int k : kept_setups) troubled.erase(k);
    }
    putBack(plan, some);
  }
  plan.useless.kept = plan.useless.found;
  plan.useless.kept_why = why;
  plan.cancelled = plan.cancelled || all.report.cancelled;
  combinePlan(plan, part, library, options);
}

}  // namespace art2part
