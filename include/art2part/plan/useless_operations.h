// Roughing operations the simulation finds removing almost nothing, left out of a verified plan (issue 19, item 5).
//
// Why the simulation decides and not the planner: roughing plans each setup against an in-process stock that is
// conservative by construction (a coarse ray model, each tool eroded so the model never loses material:
// in_process_stock.h), so a later setup may plan to rough skins the earlier setups already took. On CTC-02 setups
// 4-13's main passes were planned to remove 6-13 L each and removed 0.004-3.4 L in the simulation: hours of cutting air.
//
// The rule: a roughing operation removing under kUselessRemovalShare of what the whole roughing removes (the
// verification's per-operation figures) is left out, the plan recombined and verified again. The drop is kept only
// when that verification finds no more gouges and no more collisions than the first and leaves at most what the
// dropped operations removed beyond the first's leftover (what they took falls to the operations after them or stays);
// otherwise, when that verification found its gouges or collisions in some setups only, the useless operations of
// setups with findings are put back (the operations after one in its setup may rely on the little it took: a skin a
// rapid crosses), the others left out and the plan verified again under the same rule: first those of the earliest
// setup with findings only (setups are cut in sequence, so findings in a later setup may come from the stock an
// earlier setup's drop left), then also those of the next setup with findings in any trial so far, the third and
// last round those of every such setup. Failing all, the plan is put back exactly as it was (operations, toolpath,
// verification) and says why. Operations found useless are not looked for again: the operations after a dropped one
// cut what it left, so none of them becomes useless by the drop.
#pragma once

#include <functional>

#include "art2part/plan/plan_figures.h"
#include "art2part/plan/plan_part.h"

namespace art2part {

// Verifies a combined plan (its toolpath and tools) into `state`, as the caller's verification does (planPart: in
// process, each trial resumed from the first verification's checkpoints at the last setup change before the first
// operation left out (verify.h's SweepCheckpoint); the cell's stage chain: the verification node's service, which
// leaves `state` empty).
using PlanVerifier = std::function<VerificationReport(const PlanResult& plan, VerificationState& state)>;

// The roughing operations (indices into plan.roughing.operations) the verified plan's simulation found useless.
// Empty for a plan not verified.
std::vector<int> uselessRoughing(const PlanResult& plan);

// Leaves out plan's useless roughing operations when the plan without them verifies as clean (above); fills
// plan.useless and, when dropped, plan.roughing.dropped (one line each), plan.verification and plan.simulation.
// A cancelled re-verification keeps the plan as it was, with plan.cancelled set. Throws what combinePlan throws.
void dropUselessRoughing(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options,
                         const PlanVerifier& verify);

}  // namespace art2part
