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
  if (after.stopped_at_row > 0)
    return "the verification without " + them + " stopped at row " + std::to_string(after.stopped_at_row);
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

// Gouges and collisions of one setup's operations.
struct Findings {
  int gouges = 0, collisions = 0;
};

// By setup, what `report` (of the combined `plan`) finds.
std::map<int, Findings> findingsBySetup(const PlanResult& plan, const VerificationReport& report) {
  std::map<int, Findings> by_setup;
  for (const PlanOperation& op : plan.operations) {
    const auto check = report.by_op.find(op.index);
    if (check == report.by_op.end()) continue;
    Findings& f = by_setup[op.setup];
    f.gouges += check->second.gouges;
    f.collisions += check->second.collisions;
  }
  return by_setup;
}

// The earliest setup where `report` finds more gouges or more collisions than `planned` (the plan as planned, by
// setup); -1 when none.
int firstWorseSetup(const PlanResult& plan, const VerificationReport& report, const std::map<int, Findings>& planned) {
  for (const auto& [setup, found] : findingsBySetup(plan, report)) {
    const auto before = planned.find(setup);
    const Findings was = before == planned.end() ? Findings{} : before->second;
    if (found.gouges > was.gouges || found.collisions > was.collisions) return setup;
  }
  return -1;
}

// Why the plan without `them` is not kept, when the setup `worse` decides: its findings with and without them.
std::string worseIn(int worse, const std::map<int, Findings>& with, const std::map<int, Findings>& without,
                    const std::string& them) {
  const auto count = [](const std::map<int, Findings>& m, int setup) {
    const auto it = m.find(setup);
    return it == m.end() ? Findings{} : it->second;
  };
  const Findings a = count(with, worse), b = count(without, worse);
  const bool gouges = b.gouges > a.gouges;
  return "without " + them + " the simulation finds " + std::to_string(gouges ? b.gouges : b.collisions) +
         (gouges ? " gouges" : " collisions") + " in setup " + std::to_string(worse) + " (" +
         std::to_string(gouges ? a.gouges : a.collisions) + " with them)";
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
              const PlanVerifier& verify, const TrialSweep& sweep, Trial& trial) {
  trial.held.resize(trial.drop.size());
  for (std::size_t i = trial.drop.size(); i-- > 0;) {  // last first, so the indices hold
    trial.held[i] = std::move(plan.roughing.operations[trial.drop[i]]);
    plan.roughing.operations.erase(plan.roughing.operations.begin() + trial.drop[i]);
  }
  combinePlan(plan, part, library, options);
  trial.report = verify(plan, trial.state, sweep);
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
  plan.simulation.checkpoints.clear();
}

// The setup whose useless operations go back when `worse` finds more: its own when some of `drop` are its, else the
// latest setup before it with some; -1 when none.
int setupToPutBack(int worse, const std::vector<int>& drop, const std::map<int, int>& setup_of) {
  int back = -1;
  for (int source : drop) {
    const int k = setup_of.at(source);
    if (k <= worse) back = std::max(back, k);
  }
  return back;
}

}  // namespace

void dropUselessRoughing(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options,
                         const PlanVerifier& verify) {
  plan.useless = UselessRoughing{};
  // The sweeps to resume from: the first verification's, then also the last round's.
  std::vector<SweepCheckpoint> sweeps = std::move(plan.simulation.checkpoints);
  plan.simulation.checkpoints.clear();
  const std::size_t first_sweep = sweeps.size();
  const std::vector<int> useless = uselessRoughing(plan);
  plan.useless.found = static_cast<int>(useless.size());
  if (useless.empty()) return;

  const double roughing_removed = roughingRemoved(plan);
  std::map<int, double> removed;  // by source
  std::map<int, int> setup;       // by source
  std::set<int> setups;           // with useless operations
  for (int source : useless) {
    removed[source] = removedBy(plan, source);
    setup[source] = plan.roughing.operations[source].setup;
    setups.insert(setup[source]);
  }
  auto removedByAll = [&](const std::vector<int>& sources) {
    double sum = 0;
    for (int source : sources) sum += removed[source];
    return sum;
  };
  const std::map<int, Findings> planned = findingsBySetup(plan, plan.verification);
  const int setup_changes = static_cast<int>(plan.setups.setups.size());  // a checkpoint at each of them
  std::string why;  // why the plan without all of them is not kept
  std::set<int> kept_setups;
  bool cancelled = false;
  for (std::size_t round = 0; round < setups.size() && !cancelled; ++round) {
    Trial trial;
    for (int source : useless)
      if (!kept_setups.count(setup[source])) trial.drop.push_back(source);
    if (trial.drop.empty()) break;
    const TrialSweep sweep{sweeps, setup_changes, [&](int, const VerificationReport& so_far) {
                             return firstWorseSetup(plan, so_far, planned) < 0;
                           }};
    leaveOut(plan, part, library, options, verify, sweep, trial);
    cancelled = trial.report.cancelled;
    const int worse = cancelled ? -1 : firstWorseSetup(plan, trial.report, planned);
    const std::string them = round == 0 ? "all of them" : "them";
    const std::string not_clean = worse >= 0
                                      ? worseIn(worse, planned, findingsBySetup(plan, trial.report), them)
                                      : notAsClean(plan.verification, trial.report, removedByAll(trial.drop), them);
    if (not_clean.empty()) {
      if (!kept_setups.empty()) {
        std::string listed;
        for (int k : kept_setups) listed += (listed.empty() ? "" : ", ") + std::to_string(k);
        plan.useless.kept = static_cast<int>(useless.size() - trial.drop.size());
        plan.useless.kept_why = "those of setups " + listed + " kept: " + why;
      }
      return keep(plan, trial, removed, roughing_removed);
    }
    if (round == 0) why = not_clean;
    const int back = worse >= 0 ? setupToPutBack(worse, trial.drop, setup) : -1;
    putBack(plan, trial);
    if (back < 0) break;
    kept_setups.insert(back);
    sweeps.resize(first_sweep);  // the last round's replace the round's before
    for (SweepCheckpoint& c : trial.state.checkpoints) sweeps.push_back(std::move(c));
  }
  plan.useless.kept = plan.useless.found;
  plan.useless.kept_why = why;
  plan.cancelled = plan.cancelled || cancelled;
  combinePlan(plan, part, library, options);
}

}  // namespace art2part
