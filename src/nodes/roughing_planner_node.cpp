// roughing_planner: global roughing of a part loaded in part_server (thesis 4.1, 5.1-5.2); with the same options the
// same plan as `art2part plan`'s roughing stage (planRoughing one setup at a time).
//   action:   plan_roughing (PlanRoughing): visibility and setups here (or the goal's setups_record, plan_setups'
//             hand-off; with plug_holes the holes a drill makes stay solid, as `art2part plan` roughs), then one
//             setup at a time: the main flat or bull mill (chosen per setup, or the goal's), then optionally the rest tool; feedback between stages and
//             setups (setup k of n, the last operation, levels done); the result holds per operation a
//             MachiningOperation and the whole toolpath (tips in metres, moves); toolpaths.csv and tools.json are
//             written to the goal's output_dir when it names one
//   topics:   ~markers (MarkerArray, latched): DELETEALL, per operation its feed moves coloured by tool (ns feed_<i>)
//             and its rapids thin and grey (ns rapid_<i>), per setup its levels as squares (ns slabs_<k>), metres
//             (markers: every namespace under "<part_id>/", a DELETEALL first; marker_helpers' forPart)
//   params:   ~frame_id (default "part"), ~tools (the tool library; default the package's config/tools.yaml);
//             /art2part/output_root (cell_folders.h): output_dir must lie under it (relative: under it)
//   topics:   /diagnostics (node_diagnostics.h)
// A bad goal (unknown part or tool, a tool that cannot rough, a bad mode or number, an output_dir outside the output
// root or unwritable) is aborted with a one-line reason in result.message; the node stays up. A cancel stops the
// running one within a level; it ends preempted. A new goal waits for the running one (stage_goals.h).
#include "roughing_markers.h"  // first: the message MachiningOperation beside the core's RoughingOperation
#include "node_main.h"

#include <actionlib/server/simple_action_server.h>
#include <ros/ros.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "art2part/plan/stage_records.h"
#include "cell_folders.h"
#include "node_diagnostics.h"
#include "stage_goals.h"
#include "part_client.h"
#include "marker_helpers.h"

#ifndef ART2PART_CONFIG_DIR
#error "ART2PART_CONFIG_DIR (the package's config folder) must be defined by the build"
#endif

namespace art2part {

namespace {

// Thrown when the client cancels the goal, between two steps.
struct Preempted : std::runtime_error {
  Preempted() : std::runtime_error("preempted") {}
};

std::string oneDecimal(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", value);
  return text;
}

}  // namespace

class RoughingPlannerNode {
 public:
  RoughingPlannerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : server_(nh, "plan_roughing", [this](const PlanRoughingGoalConstPtr& goal) { execute(goal); }, false) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
    pnh.param<std::string>("tools", tools_path_, std::string(ART2PART_CONFIG_DIR) + "/tools.yaml");
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
    diagnostics_.setConfiguration("output root", folderList(folders_.plans));
    diagnostics_.setConfiguration("tools", tools_path_);
    for (const std::string& problem : folders_.problems) diagnostics_.addProblem(problem);
    server_.start();
    ROS_INFO("plan_roughing ready (tools: %s)", tools_path_.c_str());
  }

 private:
  void feedback(PlanRoughingFeedback& f) {
    server_.publishFeedback(f);
    if (cancelAsked(server_) || !ros::ok()) throw Preempted();
  }

  void execute(const PlanRoughingGoalConstPtr& goal) {
    PlanRoughingResult result;
    const auto start = std::chrono::steady_clock::now();
    NodeDiagnostics::Request request = diagnostics_.request("plan_roughing");
    try {
      // Everything the goal says is checked before the part is fetched and analysed.
      const SetupOptions setup_options = roughingSetupOptionsFrom(*goal);
      const VisibilityOptions visibility_options = roughingVisibilityOptionsFrom(*goal);
      const ToolLibrary library = loadToolLibrary(tools_path_);  // each goal: edits to the file count
      const RoughingOptions options = roughingOptionsFrom(*goal, library, tools_path_);
      const std::string output_dir =
          goal->output_dir.empty() ? "" : outputFolder(folders_, "output_dir", goal->output_dir);

      PlanRoughingFeedback f;
      f.stage = "fetching part";
      feedback(f);
      std::string id;
      const std::shared_ptr<const Part> part = parts_.get(goal->part_id, &id);

      const SetupPlan setups = goal->setups_record.empty()
                                   ? planSetupsHere(*part, visibility_options, setup_options, f)
                                   : setupsFromRecord(goal->setups_record);  // the supervisor's hand-off
      PlanOptions stage_options;  // what planPart's roughing stage does with these options
      stage_options.roughing = options;
      stage_options.finish = goal->plug_holes;
      const RoughingStage stage = roughEachSetup(*part, setups, library, stage_options, f);
      const RoughingPlan& plan = stage.roughing;
      if (!output_dir.empty()) writeRoughingFiles(plan, library, output_dir);

      fillResult(plan, result);
      result.record = roughingRecord(stage);
      result.mode = machineModeName(setups.mode);
      result.setup_count = static_cast<uint32_t>(setups.setups.size());
      result.success = true;
      result.message = summary(id, setups, plan, result, goal->output_dir);
      result.seconds = secondsSince(start);
      markers_pub_.publish(forPart(id, roughingMarkers(*part, setups, plan, options, frame_id_)));
      ROS_INFO("plan_roughing: %s", result.message.c_str());
      server_.setSucceeded(result);
      request.finish(RequestOutcome::Served, result.message);
    } catch (const std::exception& e) {  // InputError (a bad goal), a cancelled goal and anything else: no crash
      const bool stopped = dynamic_cast<const Preempted*>(&e) != nullptr;
      const bool preempted = stopped || cancelAsked(server_);
      result = PlanRoughingResult();
      result.success = false;
      result.message = stopped ? std::string("preempted") : preempted ? "preempted: " + std::string(e.what()) : e.what();
      result.seconds = secondsSince(start);
      ROS_WARN("plan_roughing: %s", result.message.c_str());
      if (preempted) server_.setPreempted(result, result.message);
      else server_.setAborted(result, result.message);
      request.finish(preempted ? RequestOutcome::Cancelled : outcomeOf(e), result.message);
    }
  }

  // Visibility and setups as plan_setups plans them, when the goal brings none.
  SetupPlan planSetupsHere(const Part& part, const VisibilityOptions& visibility_options,
                           const SetupOptions& setup_options, PlanRoughingFeedback& f) {
    f.stage = "visibility";
    feedback(f);
    auto progress = [this, &f](const ProgressReport& p) {
      f.fraction = p.fraction;
      server_.publishFeedback(f);
      return !cancelAsked(server_) && ros::ok();
    };
    const VisibilityResult visibility = analyseVisibility(part, visibility_options, progress);
    if (visibility.cancelled) throw Preempted();
    f.stage = "setups";
    f.fraction = 0;
    feedback(f);
    return planSetups(part, visibility, setup_options);
  }

  // planPart's roughing stage (holes kept solid when asked, then the core's tool choice, rest passes and stock
  // between setups, unchanged), with feedback after every level; a cancel stops it within a level.
  RoughingStage roughEachSetup(const Part& part, const SetupPlan& setups, const ToolLibrary& library,
                               const PlanOptions& options, PlanRoughingFeedback& f) {
    const int n = static_cast<int>(setups.setups.size());
    f.stage = options.finish ? "holes" : "roughing";
    f.setups = static_cast<uint32_t>(n);
    feedback(f);
    RoughingStage stage = planPartRoughing(part, setups, library, options, [&](const ProgressReport& p) {
      f.stage = "roughing";
      f.setup = static_cast<uint32_t>(std::min(n, static_cast<int>(p.fraction * n) + 1));
      f.fraction = p.fraction;
      f.levels_done = static_cast<uint32_t>(p.done);
      f.operation = p.message;
      server_.publishFeedback(f);
      return !cancelAsked(server_) && ros::ok();
    });
    if (stage.roughing.cancelled) throw Preempted();
    f.stage = "done";
    f.fraction = 1;
    f.operations = static_cast<uint32_t>(stage.roughing.operations.size());
    server_.publishFeedback(f);
    return stage;
  }

  static std::string summary(const std::string& id, const SetupPlan& setups, const RoughingPlan& plan,
                             const PlanRoughingResult& result, const std::string& output_dir) {
    double cutting_m = 0, estimated_s = 0;
    for (const MachiningOperation& op : result.operations) {
      cutting_m += op.cutting_length_m;
      estimated_s += op.estimated_time_s;
    }
    std::string text = "part '" + id + "': " + std::to_string(setups.setups.size()) +
                       (setups.setups.size() == 1 ? " setup (" : " setups (") + machineModeName(setups.mode) + "), " +
                       std::to_string(plan.operations.size()) +
                       (plan.operations.size() == 1 ? " operation, " : " operations, ") +
                       std::to_string(result.tips.size()) + " points, " + oneDecimal(cutting_m) + " m cutting, ~" +
                       std::to_string(static_cast<long>(estimated_s)) + " s machining";
    if (!output_dir.empty()) text += "; wrote " + output_dir + "/{toolpaths.csv,tools.json}";
    return text;
  }


  const CellFolders folders_ = readCellFolders(true);
  NodeDiagnostics diagnostics_;
  actionlib::SimpleActionServer<PlanRoughingAction> server_;
  std::string frame_id_, tools_path_;
  ros::Publisher markers_pub_;
  PartClient parts_;  // only the action's thread uses it
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 1 thread: goals and cancels arrive while the action's thread plans.
  return art2part::runNode<art2part::RoughingPlannerNode>(argc, argv, "roughing_planner", 1);
}
