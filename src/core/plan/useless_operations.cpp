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
  std::string why = notAsClean(plan.verification, all.report, removedByAll(useless));
  Trial* kept_trial = why.empty() ? &all : nullptr;
  Trial some;
  if (!why.empty() && !all.report.cancelled) {
    // Second round: the operations after a useless one in its setup may rely on the little it took (a skin a rapid
    // crosses); keep the useless operations of the setups where the simulation without them finds something, leave
    // out the others.
    const std::set<int> troubled = setupsWithFindings(plan, all.report);
    for (int source : useless)
      if (!troubled.count(setup[source])) some.drop.push_back(source);
    if (!troubled.empty() && !some.drop.empty()) {
      putBack(plan, all);
      leaveOut(plan, part, library, options, verify, some);
      if (notAsClean(plan.verification, some.report, removedByAll(some.drop)).empty()) {
        kept_trial = &some;
        plan.useless.kept = static_cast<int>(useless.size() - some.drop.size());
        std::string listed;
        for (int k : troubled) listed += (listed.empty() ? "" : ", ") + std::to_string(k);
        plan.useless.kept_why = "those of setups " + listed + " kept: " +
                                notAsClean(plan.verification, all.report, removedByAll(useless), "all of them");
      } else {
        putBack(plan, some);
        some.drop.clear();
        all.drop.clear();  // everything is back in
      }
    }
  }
  if (kept_trial) {
    plan.useless.dropped = true;
    for (std::size_t i = 0; i < kept_trial->drop.size(); ++i)
      plan.roughing.dropped.push_back(
          droppedBySimulation(kept_trial->held[i], removed[kept_trial->drop[i]], roughing_removed));
    plan.verification = std::move(kept_trial->report);
    plan.simulation = std::move(kept_trial->state);
    return;
  }
  plan.useless.kept = plan.useless.found;
  plan.useless.kept_why = why;
  plan.cancelled = plan.cancelled || all.report.cancelled || some.report.cancelled;
  putBack(plan, all);
  combinePlan(plan, part, library, options);
}

}  // namespace art2part
