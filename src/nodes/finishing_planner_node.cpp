// finishing_planner: face-based finishing of a part loaded in part_server (thesis 4.2-4.3); with the same options the
// same finishing as `art2part plan` (planPart: visibility, setups and any added for finishing, holes, roughing, then
// finishing; no verification: that is verify_toolpaths' job), or, when the goal hands on the stages before it
// (visibility, setups_record, roughing_record: the cell supervisor's chain), finishing alone on them; the result's
// record holds the whole finishing plan (stage_records.h).
//   action:   plan_finishing (PlanFinishing): feedback at every stage and group of faces (stage, fraction, message);
//             the result holds the finishing operations (MachiningOperation), every face's FaceFinishing, the
//             finishing toolpath (tips in metres, axes, moves); toolpaths.csv and tools.json of the finishing are
//             written to the goal's output_dir when it names one
//   topics:   ~markers (MarkerArray, latched): DELETEALL, finishing feeds by operation kind (ns finishing_<kind>),
//             rapids (ns finishing_rapids), per face its tool direction as an arrow (ns face_directions), metres
//             (markers: every namespace under "<part_id>/", a DELETEALL first; marker_helpers' forPart)
//   params:   ~frame_id (default "part"), ~tools (the tool library; default the package's config/tools.yaml);
//             /art2part/output_root (cell_folders.h): output_dir must lie under it (relative: under it)
//   topics:   /diagnostics (node_diagnostics.h)
// A bad goal (unknown part, bad mode, level or length, an output_dir outside the output root or unwritable) is
// aborted with a one-line reason in result.message; the node stays up. A cancel stops the plan at the next stage or
// group of faces; it ends preempted. A new goal waits for the running one (stage_goals.h).
#include "node_main.h"
#include "setup_markers.h"  // visibilityFromMessage

#include <actionlib/server/simple_action_server.h>
#include <ros/ros.h>

#include <chrono>
#include <filesystem>
#include <memory>

#include "art2part/plan/stage_records.h"
#include "cell_folders.h"
#include "art2part/plan/plan_folder.h"
#include "finishing_markers.h"
#include "node_diagnostics.h"
#include "stage_goals.h"
#include "part_client.h"
#include "marker_helpers.h"

#ifndef ART2PART_CONFIG_DIR
#error "ART2PART_CONFIG_DIR (the package's config folder) must be defined by the build"
#endif

namespace art2part {

class FinishingPlannerNode {
 public:
  FinishingPlannerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : server_(nh, "plan_finishing", [this](const PlanFinishingGoalConstPtr& goal) { execute(goal); }, false) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
    pnh.param<std::string>("tools", tools_path_, std::string(ART2PART_CONFIG_DIR) + "/tools.yaml");
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
    diagnostics_.setConfiguration("output root", folderList(folders_.plans));
    diagnostics_.setConfiguration("tools", tools_path_);
    for (const std::string& problem : folders_.problems) diagnostics_.addProblem(problem);
    server_.start();
    ROS_INFO("plan_finishing ready (tools: %s)", tools_path_.c_str());
  }

 private:
  void execute(const PlanFinishingGoalConstPtr& goal) {
    PlanFinishingResult result;
    const auto start = std::chrono::steady_clock::now();
    NodeDiagnostics::Request request = diagnostics_.request("plan_finishing");
    try {
      const PlanOptions options = finishingPlanOptionsFrom(*goal);  // checked before anything is fetched
      const std::string output_dir =
          goal->output_dir.empty() ? "" : outputFolder(folders_, "output_dir", goal->output_dir);
      const ToolLibrary library = loadToolLibrary(tools_path_);
      PlanFinishingFeedback f;
      f.stage = "fetching part";
      server_.publishFeedback(f);
      std::string id;
      const std::shared_ptr<const Part> part = parts_.get(goal->part_id, &id);
      const ProgressSink progress = [this](const ProgressReport& p) {
        PlanFinishingFeedback feedback;
        feedback.stage = p.stage;
        feedback.fraction = p.fraction;
        feedback.message = p.message;
        server_.publishFeedback(feedback);
        return !cancelAsked(server_) && ros::ok();
      };
      const PlanResult plan = handsOn(*goal) ? finishHandedOn(*goal, *part, library, options, progress)
                                             : planPart(*part, library, options, progress);
      if (plan.cancelled) {
        result.success = false;
        result.message = "preempted";
        result.seconds = secondsSince(start);
        server_.setPreempted(result, result.message);
        request.finish(RequestOutcome::Cancelled, result.message);
        return;
      }
      fillFinishingResult(*part, plan, result);
      result.record = finishingRecord(plan.finishing);
      if (!output_dir.empty()) writeFiles(plan, output_dir);
      result.mode = machineModeName(plan.setups.mode);
      result.success = true;
      result.seconds = secondsSince(start);
      result.message = summary(id, result, goal->output_dir);
      f.stage = "done";
      f.fraction = 1;
      server_.publishFeedback(f);
      markers_pub_.publish(forPart(id, finishingMarkers(*part, plan, frame_id_)));
      ROS_INFO("plan_finishing: %s", result.message.c_str());
      server_.setSucceeded(result);
      request.finish(RequestOutcome::Served, result.message);
    } catch (const std::exception& e) {  // InputError (a bad goal) and anything else: no crash
      const bool preempted = cancelAsked(server_);
      result = PlanFinishingResult();
      result.success = false;
      result.message = preempted ? "preempted: " + std::string(e.what()) : e.what();
      result.seconds = secondsSince(start);
      ROS_WARN("plan_finishing: %s", result.message.c_str());
      if (preempted) server_.setPreempted(result, result.message);
      else server_.setAborted(result, result.message);
      request.finish(preempted ? RequestOutcome::Cancelled : outcomeOf(e), result.message);
    }
  }

  // The goal carries the stages before finishing (the supervisor's hand-off): all four fields, or none.
  static bool handsOn(const PlanFinishingGoal& goal) {
    const int given = !goal.directions.empty() + !goal.bits.empty() + !goal.setups_record.empty() +
                      !goal.roughing_record.empty();
    if (given != 0 && given != 4)
      throw InputError("directions, bits, setups_record and roughing_record come together: " + std::to_string(given) +
                       " of 4 given");
    return given == 4;
  }

  // Finishing on the stages handed on, then combined with roughing as planPart combines them (the markers and the
  // files show the finishing operations of the whole plan).
  static PlanResult finishHandedOn(const PlanFinishingGoal& goal, const Part& part, const ToolLibrary& library,
                                   const PlanOptions& options, const ProgressSink& progress) {
    PlanResult plan;
    plan.visibility = visibilityFromMessage(part, goal.directions, goal.bits, goal.special);
    plan.setups = setupsFromRecord(goal.setups_record);
    const RoughingStage roughing = roughingFromRecord(goal.roughing_record);
    if (plan.visibility.map.triangles() != part.mesh.triangleCount())
      throw InputError("the visibility handed on is of another part");
    plan.holes = roughing.holes;
    plan.hole_methods = roughing.hole_methods;
    plan.roughing = roughing.roughing;
    plan.finishing = planPartFinishing(part, plan.visibility, plan.setups, roughing, library, options, progress);
    plan.cancelled = plan.finishing.cancelled;
    if (!plan.cancelled) combinePlan(plan, part, library, options);
    return plan;
  }

  static void writeFiles(const PlanResult& plan, const std::string& folder) {
    const Toolpath path = finishingToolpath(plan);
    std::vector<Tool> tools;
    for (const Tool& t : plan.tools)
      if (std::any_of(path.begin(), path.end(), [&](const CutterLocation& c) { return c.tool == t.id; }))
        tools.push_back(t);
    writeToolpathFiles(folder, path, tools);
  }

  static std::string summary(const std::string& id, const PlanFinishingResult& result, const std::string& output_dir) {
    int finished = 0, partial = 0, unmachinable = 0;
    for (const FaceFinishing& f : result.faces) {
      finished += f.status == "finished";
      partial += f.status == "partial";
      unmachinable += f.status == "unmachinable";
    }
    std::string text = "part '" + id + "': " + std::to_string(result.operations.size()) + " finishing operations in " +
                       std::to_string(result.setup_count) + " setups (" + std::to_string(result.finishing_setups) +
                       " added for finishing), " + std::to_string(result.tool_changes) + " tool changes, " +
                       std::to_string(result.holes_drilled) + " holes drilled; faces: " + std::to_string(finished) +
                       " finished, " + std::to_string(partial) + " partial, " + std::to_string(unmachinable) +
                       " unmachinable; ~" + std::to_string(static_cast<long>(result.estimated_time_s)) + " s machining";
    if (!output_dir.empty()) text += "; wrote " + output_dir + "/{toolpaths.csv,tools.json}";
    return text;
  }


  const CellFolders folders_ = readCellFolders(true);
  NodeDiagnostics diagnostics_;
  actionlib::SimpleActionServer<PlanFinishingAction> server_;
  std::string frame_id_, tools_path_;
  ros::Publisher markers_pub_;
  PartClient parts_;  // only the action's thread uses it
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 1 thread: goals and cancels arrive while the action's thread plans.
  return art2part::runNode<art2part::FinishingPlannerNode>(argc, argv, "finishing_planner", 1);
}
