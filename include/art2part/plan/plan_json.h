// plan.json of the file contract: the part, the directions sampled, the setups, what no setup reaches, every operation
// (roughing and finishing: setup, kind, tool, points, length, time, removed volume), every face with its operations
// and tools or the reason it stays unmachinable, the holes and how each is made, the verification's figures, the
// machining time and the stage timings.
#pragma once

#include <nlohmann/json.hpp>

#include "art2part/kinematics/machine.h"
#include "art2part/plan/plan_part.h"

namespace art2part {

// The whole plan; the caller adds what only it knows (load and post timings, the program written). Times are on
// `machine` (plan_figures.h): a machine without joints stands for motionLimits' documented default.
nlohmann::json planJson(const Part& part, const PlanResult& plan, const Machine& machine = Machine{});

// Pieces, for the nodes.
nlohmann::json holeJson(const Hole& hole, const HoleMachining& method);
nlohmann::json faceFinishJson(const Part& part, const FaceFinish& face);
nlohmann::json verificationJson(const VerificationReport& report);

}  // namespace art2part
