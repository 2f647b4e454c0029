// The plan folder's pictures (OSMesa renders): the part coloured by setup, and the stock the simulation leaves.
#pragma once

#include <string>

#include "art2part/plan/plan_part.h"

namespace art2part {

// setups.png: each triangle in the colour of the setup that machines it (setupColour), what no setup reaches red.
// Throws InputError when the file cannot be written.
void writeSetupPicture(const Part& part, const SetupPlan& plan, const std::string& path);

// remaining.png: the stock the plan's simulation leaves, coloured by its thickness over the part (needs
// plan.verified). Throws InputError when the file cannot be written.
void writeRemainingPicture(const Part& part, const PlanResult& plan, const std::string& path);
// The same from a simulation's report and state (the verification node's, where the simulation ran).
void writeRemainingPicture(const Part& part, const VerificationReport& report, const VerificationState& simulation,
                           const std::string& path);

}  // namespace art2part
