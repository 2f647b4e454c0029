// The cell's pipeline through the stage nodes: the supervisor's plan_part runs visibility, setups, roughing, finishing
// and verification by calling analyse_visibility, plan_setups, plan_roughing, plan_finishing and verify_toolpaths in
// planPart's order, each stage taking the previous one's result as a message (stage records, stage_records.h), and
// assembles from the results the plan planPart makes in one process. Every algorithm stays in the stage nodes (the
// core); this only translates and waits.
//
// A stage that is not offered, whose node goes away, that fails or that the caller stops ends the chain with an
// exception naming the stage; a goal sent to an action is cancelled when the chain stops waiting for it.
#pragma once

#include <actionlib/client/simple_action_client.h>
#include <ros/ros.h>

#include <art2part/AnalyseVisibilityAction.h>
#include <art2part/PlanFinishingAction.h>
#include <art2part/PlanPartAction.h>
#include <art2part/PlanRoughingAction.h>

#include <functional>
#include <stdexcept>
#include <string>

#include "art2part/common/progress.h"
#include "art2part/plan/plan_part.h"

namespace art2part {

// A stage could not give its result: its node is missing or went away, or it failed. what(): "stage 'roughing': ...".
struct StageFailure : std::runtime_error {
  StageFailure(const std::string& stage_name, const std::string& reason)
      : std::runtime_error("stage '" + stage_name + "': " + reason), stage(stage_name) {}
  std::string stage;
};

// The progress sink answered stop (a cancel or a timeout the supervisor saw): the chain stopped at `stage`.
struct StageStopped : std::runtime_error {
  explicit StageStopped(const std::string& stage_name)
      : std::runtime_error("stopped in stage '" + stage_name + "'"), stage(stage_name) {}
  std::string stage;
};

struct StageChainOptions {
  double server_wait_s = 20;  // how long a stage may take to be offered (a respawned node starting) before it fails
  double poll_s = 0.1;        // how often a wait looks at the sink's answer and at the node's connection
};

// An action's goal, result and feedback messages (SimpleActionClient keeps its own names private).
template <class Action>
using GoalOf = typename Action::_action_goal_type::_goal_type;
template <class Action>
using ResultPtrOf = boost::shared_ptr<const typename Action::_action_result_type::_result_type>;
template <class Action>
using FeedbackPtrOf = boost::shared_ptr<const typename Action::_action_feedback_type::_feedback_type>;

class StageChain {
 public:
  explicit StageChain(StageChainOptions options = {});

  // The whole pipeline for `part` (loaded in part_server as `part_id`; its record, so the stages see the same
  // triangles) with planPart's `options` (from `goal`: mode and scallop are forwarded as the goal gave them). The
  // verification node draws what is left to `picture_file` when it is not empty. Feedback of every stage goes to
  // `progress` (its answer is not asked); `go_on` is asked at least every poll_s while a stage works, and false stops
  // the chain (StageStopped; an action's goal is cancelled). Timings per stage, wall clock.
  PlanResult run(const PlanPartGoal& goal, const std::string& part_id, const Part& part, const ToolLibrary& library,
                 const PlanOptions& options, const std::string& picture_file, const ProgressSink& progress,
                 const std::function<bool()>& go_on);

 private:
  template <class Action>
  ResultPtrOf<Action> callAction(actionlib::SimpleActionClient<Action>& client, const std::string& stage,
                                 const GoalOf<Action>& goal,
                                 const std::function<void(const FeedbackPtrOf<Action>&)>& on_feedback,
             const ProgressSink& progress, const std::function<bool()>& go_on);

  template <class Service>
  Service callService(const std::string& name, const std::string& stage, const Service& request,
                      const ProgressSink& progress, const std::function<bool()>& go_on);

  StageChainOptions options_;
  actionlib::SimpleActionClient<AnalyseVisibilityAction> visibility_;
  actionlib::SimpleActionClient<PlanRoughingAction> roughing_;
  actionlib::SimpleActionClient<PlanFinishingAction> finishing_;
};

}  // namespace art2part
