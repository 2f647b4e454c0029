// Roughing operations the simulation finds removing almost nothing, left out of a verified plan (issue 19, item 5).
//
// Why the simulation decides and not the planner: roughing plans each setup against an in-process stock that is
// conservative by construction (a coarse ray model, each tool eroded so the model never loses material:
// in_process_stock.h), so a later setup may plan to rough skins the earlier setups already took. On CTC-02 setups
// 4-13's main passes were planned to remove 6-13 L each and removed 0.004-3.4 L in the simulation: hours of cutting air.
//
// The rule: a roughing operation removing under kUselessRemovalShare of what the whole roughing removes (the
// verification's per-operation figures) is left out, the plan recombined and verified again. The drop is kept only
// when that verification finds, in no setup, more gouges or more collisions than the plan as planned, and leaves at
// most what the dropped operations removed beyond the first's leftover (what they took falls to the operations after
// them or stays). Otherwise, round after round: the setups are cut in sequence, so the earliest setup where the
// simulation finds more decides. When that setup had useless operations left out, they are put back (the operations
// after one in its setup may rely on the little it took: a skin a rapid crosses); when it had none, those of the
// latest setup before it that had some (the stock their drop left reaches it); the others stay out and the plan is
// verified again. At most one round per setup with useless operations; failing all, the plan is put back exactly as
// it was (operations, toolpath, verification) and says why. Operations found useless are not looked for again: the
// operations after a dropped one cut what it left, so none of them becomes useless by the drop.
//
// Cost: a round reads no finding past the earliest setup with more, so its sweep stops there, and each resumes from
// the checkpoints of the sweeps before it (the first verification's, the last round's) at the last setup change its
// rows share with them: about one sweep from the first setup with useless operations, plus each setup put back once
// more (CTC-02, four rounds: 462 s sweeping each whole, 124 s so, the same decisions).
#pragma once

#include <functional>

#include "art2part/plan/plan_figures.h"
#include "art2part/plan/plan_part.h"

namespace art2part {

// What a round's verification may take (verifyToolpath's resume_from, VerifyOptions::checkpoints and
// keep_sweeping). A verifier that ignores it and sweeps the whole path (the cell's stage chain: the verification
// node's service) gets the same decisions: the rule reads no finding past the setup where keep_sweeping stops.
struct TrialSweep {
  const std::vector<SweepCheckpoint>& resume_from;  // the sweeps so far: resume from the latest whose rows match
  int checkpoints = 0;                               // to keep in the state, for the rounds after
  std::function<bool(int row, const VerificationReport& so_far)> keep_sweeping;  // false: stop the sweep at row
};

// Verifies a combined plan (its toolpath and tools) into `state`, as the caller's verification does (planPart: in
// process, with `trial`; the cell's stage chain: the verification node's service, which leaves `state` empty).
using PlanVerifier =
    std::function<VerificationReport(const PlanResult& plan, VerificationState& state, const TrialSweep& trial)>;

// The roughing operations (indices into plan.roughing.operations) the verified plan's simulation found useless.
// Empty for a plan not verified.
std::vector<int> uselessRoughing(const PlanResult& plan);

// Leaves out plan's useless roughing operations when the plan without them verifies as clean (above); fills
// plan.useless and, when dropped, plan.roughing.dropped (one line each), plan.verification and plan.simulation.
// plan.simulation.checkpoints (the first verification's, VerifyOptions::checkpoints) are the first round's to resume
// from; they are gone after. A cancelled re-verification keeps the plan as it was, with plan.cancelled set. Throws
// what combinePlan throws.
void dropUselessRoughing(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options,
                         const PlanVerifier& verify);

}  // namespace art2part
