// plan.json of the file contract: the part, the directions sampled, the setups, what no setup reaches, every operation
// (roughing and finishing: setup, kind, tool, points, length, time), every face with its operations and tools or the
// reason it stays unmachinable, the holes and how each is made, the verification's figures and the stage timings.
#pragma once

#include <nlohmann/json.hpp>

#include "art2part/plan/plan_part.h"

namespace art2part {

// The whole plan; the caller adds what only it knows (load and post timings, the program written).
nlohmann::json planJson(const Part& part, const PlanResult& plan);

// Pieces, for the nodes.
nlohmann::json holeJson(const Hole& hole, const HoleMachining& method);
nlohmann::json faceFinishJson(const Part& part, const FaceFinish& face);
nlohmann::json verificationJson(const VerificationReport& report);

}  // namespace art2part
