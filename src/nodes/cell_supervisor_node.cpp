// cell_supervisor: the cell's single call. One plan_part goal turns a part into a plan folder and a program.
//   action:   plan_part (PlanPart): goals queue (at most ~max_queue waiting; more are rejected with the reason); the
//             running goal has part_server load the part, then runs the pipeline through the stage nodes
//             (stage_chain.h: analyse_visibility, plan_setups, plan_roughing, plan_finishing, verify_toolpaths, each
//             taking the previous stage's result; planPart's plan), then writes the plan folder (writePlanFolder:
//             plan.json, toolpaths.csv, tools.json, mesh.stl, pictures, program.ngc for the machine) under
//             ~output_root. Feedback at every stage report and at least once a second (a heartbeat repeats the
//             last one); a cancel ends the goal PREEMPTED within a second; a stage running longer than its timeout
//             (~stage_timeouts) ends it ABORTED naming the stage.
//   services: list_plans (ListPlans), get_plan (GetPlan): the plan folders under ~output_root.
//   params:   /art2part/part_folders and /art2part/output_root (launch/folders.launch: part_file must lie in the
//             first, plans are written under the second), ~tools, ~machines_dir, ~machine_3axis, ~machine_5axis,
//             ~max_queue, ~stage_timeouts (dict, s), ~default_timeout (s).
//   topics:   /diagnostics (NodeDiagnostics: busy or idle, goals served, refused, failed, cancelled).
// A bad goal is aborted with a one-line reason; a stage node that is missing, dies or fails aborts the goal naming the
// stage ("stage 'roughing': its node went away ..."); the node serves the next one.
#include <actionlib/server/action_server.h>
#include <ros/ros.h>

#include <art2part/GetPlan.h>
#include <art2part/LoadPart.h>
#include <art2part/ListPlans.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "node_main.h"
#include "art2part/plan/plan_folder.h"
#include "art2part/tooling/tool.h"
#include "cell_folders.h"
#include "node_diagnostics.h"
#include "part_client.h"
#include "stage_chain.h"
#include "supervisor_requests.h"

#ifndef ART2PART_CONFIG_DIR
#error "ART2PART_CONFIG_DIR (the package's config folder) must be defined by the build"
#endif

namespace art2part {

namespace {

using Server = actionlib::ActionServer<PlanPartAction>;
using GoalHandle = Server::GoalHandle;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

constexpr double kFeedbackPeriod = 0.25;  // s: stage reports closer than this are not all published
constexpr double kHeartbeat = 0.5;        // s: the last feedback is repeated when none went out for this long
constexpr double kWatch = 0.1;            // s: how often the watch looks at the running goal
constexpr double kCancelGrace = 0.8;      // s: a cancelled stage that has not stopped by then is left to finish alone
constexpr double kServerWait = 20;        // s a stage's node may take to be offered (a respawned one starting)

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

SupervisorConfig readConfig(ros::NodeHandle& pnh) {
  SupervisorConfig c;
  pnh.param<std::string>("tools", c.tools, std::string(ART2PART_CONFIG_DIR) + "/tools.yaml");
  pnh.param<std::string>("machines_dir", c.machines_dir, std::string(ART2PART_CONFIG_DIR) + "/machines");
  pnh.param("machine_3axis", c.machine_3axis, c.machine_3axis);
  pnh.param("machine_5axis", c.machine_5axis, c.machine_5axis);
  pnh.param("max_queue", c.max_queue, c.max_queue);
  pnh.param("default_timeout", c.default_timeout, c.default_timeout);
  pnh.param("stage_timeouts", c.stage_timeouts, c.stage_timeouts);
  return c;
}

}  // namespace

class CellSupervisorNode {
 public:
  CellSupervisorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : config_(readConfig(pnh)),
        folders_(readCellFolders(true)),
        output_root_(folders_.plans.roots.empty() ? std::string() : folders_.plans.roots.front()),
        server_(nh, "plan_part", [this](GoalHandle gh) { onGoal(gh); }, [this](GoalHandle gh) { onCancel(gh); },
                false) {
    for (const std::string& problem : folders_.problems) diagnostics_.addProblem(problem);
    diagnostics_.setConfiguration("part folders", folderList(folders_.parts));
    diagnostics_.setConfiguration("output root", output_root_);
    list_srv_ = nh.advertiseService("list_plans", &CellSupervisorNode::listPlans, this);
    get_srv_ = nh.advertiseService("get_plan", &CellSupervisorNode::getPlan, this);
    heartbeat_ = nh.createWallTimer(ros::WallDuration(kWatch), [this](const ros::WallTimerEvent&) { beat(); });
    worker_ = std::thread([this] { work(); });
    server_.start();
    ROS_INFO("plan_part ready (output root %s; part folders %s)", output_root_.c_str(),
             folderList(folders_.parts).c_str());
  }

  ~CellSupervisorNode() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      cancel_ = true;
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
  }

 private:
  // ---- the queue -------------------------------------------------------------------------------------------------
  void onGoal(GoalHandle gh) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (static_cast<int>(queue_.size()) >= config_.max_queue) {
      PlanPartResult r;
      r.reason = "the cell is busy: " + std::to_string(queue_.size()) + " goals wait (max_queue " +
                 std::to_string(config_.max_queue) + "); try again later";
      gh.setRejected(r, r.reason);
      return;
    }
    gh.setAccepted();
    queue_.push_back(gh);
    PlanPartFeedback f;
    f.stage = "queued";
    f.message = std::to_string(queue_.size() - (running_ ? 0 : 1)) + " goal(s) ahead";
    gh.publishFeedback(f);
    wake_.notify_all();
  }

  void onCancel(GoalHandle gh) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = queue_.begin(); it != queue_.end(); ++it)
      if (it->getGoalID().id == gh.getGoalID().id) {
        PlanPartResult r;
        r.reason = "cancelled while queued";
        it->setCanceled(r, r.reason);
        queue_.erase(it);
        return;
      }
    if (running_ && active_.getGoalID().id == gh.getGoalID().id) {
      cancel_ = true;
      cancel_asked_ = Clock::now();
    }
  }

  void work() {
    while (true) {
      GoalHandle gh;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
        if (stopping_) return;
        gh = queue_.front();
        queue_.pop_front();
        active_ = gh;
        running_ = true;
        finished_ = false;
        cancel_ = false;
        timed_out_.clear();
        stage_ = "loading";
        stage_start_ = Clock::now();
        last_feedback_ = PlanPartFeedback();
        last_feedback_.stage = stage_;
      }
      run(gh);
      std::lock_guard<std::mutex> lock(mutex_);
      running_ = false;
    }
  }

  // Ends the running goal once: the worker's result, or the heartbeat's on a cancel or timeout the stage ignores.
  // actionlib's goal handles take the action server's lock, and actionlib holds that lock while it calls onGoal and
  // onCancel (which take mutex_): so the worker and the watch never call a goal handle while they hold mutex_.
  void finish(GoalHandle& gh, const PlanPartResult& r, int status) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (finished_) return;
      finished_ = true;
    }
    if (status == actionlib_msgs::GoalStatus::SUCCEEDED) gh.setSucceeded(r, r.reason);
    else if (status == actionlib_msgs::GoalStatus::PREEMPTED) gh.setCanceled(r, r.reason);
    else gh.setAborted(r, r.reason);
  }

  // ---- one goal --------------------------------------------------------------------------------------------------
  void run(GoalHandle gh) {
    const PlanPartGoal goal = *gh.getGoal();
    NodeDiagnostics::Request request = diagnostics_.request("plan_part " + (goal.part_file.empty() ? goal.part_id : goal.part_file));
    PlanPartResult result;
    try {
      const PlanOptions options = planOptionsFrom(goal);
      const Machine machine = loadMachine(machineFileFor(goal, config_));
      const ToolLibrary library = loadToolLibrary(config_.tools);
      report("loading", 0, goal.part_file.empty() ? "part '" + goal.part_id + "' from part_server" : goal.part_file);
      const std::string part_id = goal.part_file.empty() ? goal.part_id : loadIntoPartServer(goal);
      const std::shared_ptr<const Part> part = parts_.get(part_id);
      const std::string dir = (fs::path(output_root_) / newPlanFolderName(output_root_, part->source)).string();
      fs::create_directories(dir);  // remaining.png is drawn there by the verification node
      PlanResult plan;
      try {
        plan = chain_.run(goal, part_id, *part, library, options, (fs::path(dir) / "remaining.png").string(),
                          [this](const ProgressReport& p) { return report(p.stage, p.fraction, p.message); },
                          [this] { return !stopRequested(); });
      } catch (...) {
        std::error_code error;
        fs::remove_all(dir, error);  // no half plan under the output root
        throw;
      }
      report("writing", 0, "the plan folder and the program");
      PlanFolderOptions folder;
      folder.remaining_picture = false;  // the verification node's
      folder.program.machine = machine;
      folder.program.clampings = setupClampings(machine, *part, plan.setups, options.roughing);
      const WrittenPlan written = writePlanFolder(dir, *part, plan, folder);
      if (stopRequested()) {
        request.finish(RequestOutcome::Cancelled, "cancelled");
        return endStopped(gh);
      }
      result.success = true;
      result.output_dir = dir;
      result.summary_json = planSummary(written.plan).dump();
      report("done", 1, "wrote " + dir);
      ROS_INFO("plan_part: %s -> %s", part->source.c_str(), dir.c_str());
      finish(gh, result, actionlib_msgs::GoalStatus::SUCCEEDED);
      request.finish(RequestOutcome::Served, "wrote " + dir);
    } catch (const StageStopped&) {
      request.finish(RequestOutcome::Cancelled, "cancelled");
      return endStopped(gh);
    } catch (const std::exception& e) {  // InputError (a bad goal, a part that will not load), StageFailure, the rest
      if (stopRequested()) {
        request.finish(RequestOutcome::Cancelled, "cancelled");
        return endStopped(gh);
      }
      result = PlanPartResult();
      result.reason = e.what();
      ROS_WARN("plan_part: %s", result.reason.c_str());
      request.finish(outcomeOf(e), result.reason);
      finish(gh, result, actionlib_msgs::GoalStatus::ABORTED);
    }
  }

  // part_server loads the goal's file (confined to the part folders here first, with the same refusal as every node):
  // the stage nodes plan on the part it serves. Its id.
  std::string loadIntoPartServer(const PlanPartGoal& goal) {
    LoadPart load;
    load.request.path = confinedField(folders_.parts, "part_file", goal.part_file);
    load.request.units = goal.units;
    if (!ros::service::waitForService("load_part", ros::Duration(kServerWait)))
      throw StageFailure("loading", "no node offers load_part (part_server)");
    if (!ros::service::call("load_part", load)) throw StageFailure("loading", "the call to load_part failed");
    if (!load.response.success) throw InputError(load.response.message);
    return load.response.part_id;
  }

  bool stopRequested() {
    std::lock_guard<std::mutex> lock(mutex_);
    return cancel_ || !timed_out_.empty() || !ros::ok();
  }

  void endStopped(GoalHandle& gh) {
    PlanPartResult r;
    std::string timed_out;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      timed_out = timed_out_;
    }
    r.reason = timed_out.empty() ? "cancelled" : timed_out;
    finish(gh, r, timed_out.empty() ? actionlib_msgs::GoalStatus::PREEMPTED : actionlib_msgs::GoalStatus::ABORTED);
  }

  // The progress sink: records the stage (its start, for the timeout), publishes at most every kFeedbackPeriod, and
  // answers whether to go on.
  bool report(const std::string& stage, double fraction, const std::string& message) {
    PlanPartFeedback feedback;
    GoalHandle gh;
    bool publish = false, go_on = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stage != stage_) {
        stage_ = stage;
        stage_start_ = Clock::now();
      }
      last_feedback_.stage = stage;
      last_feedback_.fraction = fraction;
      last_feedback_.message = message;
      publish = since(last_published_) >= kFeedbackPeriod && !finished_;
      if (publish) last_published_ = Clock::now();
      feedback = last_feedback_;
      gh = active_;
      go_on = !cancel_ && timed_out_.empty() && ros::ok();
    }
    if (publish) gh.publishFeedback(feedback);
    return go_on;
  }

  double timeoutOf(const std::string& stage) const {
    const auto it = config_.stage_timeouts.find(stage);
    return it != config_.stage_timeouts.end() ? it->second : config_.default_timeout;
  }

  // The watch: repeats the last feedback when none went out for kHeartbeat, fails a stage past its timeout, and ends a
  // cancelled goal whose stage has not stopped within kCancelGrace (its result, when it comes, is dropped).
  void beat() {
    GoalHandle gh;
    PlanPartFeedback feedback;
    PlanPartResult r;
    bool publish = false, end = false, aborted = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!running_ || finished_) return;
      gh = active_;
      publish = since(last_published_) >= kHeartbeat;
      if (publish) last_published_ = Clock::now();
      feedback = last_feedback_;
      if (timed_out_.empty() && since(stage_start_) > timeoutOf(stage_))
        timed_out_ = "stage '" + stage_ + "' ran past its timeout of " + std::to_string(timeoutOf(stage_)) + " s";
      const bool late_cancel = cancel_ && since(cancel_asked_) > kCancelGrace;
      if (late_cancel || !timed_out_.empty()) {
        finished_ = end = true;
        aborted = !timed_out_.empty();
        r.reason = aborted ? timed_out_ : "cancelled (stage '" + stage_ + "' still stopping)";
      }
    }
    if (publish) gh.publishFeedback(feedback);
    if (!end) return;
    if (aborted) gh.setAborted(r, r.reason);
    else gh.setCanceled(r, r.reason);
    ROS_WARN("plan_part: %s", r.reason.c_str());
  }

  // ---- services ----------------------------------------------------------------------------------------------------
  bool listPlans(ListPlans::Request&, ListPlans::Response& res) {
    res.names = listPlanFolders(output_root_);
    for (const std::string& name : res.names) {
      std::string part;
      try {
        const nlohmann::json plan = readPlanJson((fs::path(output_root_) / name).string());
        if (plan.is_object() && plan.contains("part")) part = plan["part"].value("source", "");
      } catch (const std::exception&) {
      }
      res.parts.push_back(part);
    }
    res.success = true;
    res.message = std::to_string(res.names.size()) + " plans under " + output_root_;
    return true;
  }

  bool getPlan(GetPlan::Request& req, GetPlan::Response& res) {
    try {
      checkPlanName(req.name);
      const std::string dir = (fs::path(output_root_) / req.name).string();
      const nlohmann::json plan = readPlanJson(dir);
      if (plan.is_null()) throw InputError("no plan '" + req.name + "' under the output root");
      res.output_dir = dir;
      res.plan_json = plan.dump();
      res.summary_json = planSummary(plan).dump();
      res.success = true;
    } catch (const std::exception& e) {
      res.success = false;
      res.message = e.what();
    }
    return true;
  }

  SupervisorConfig config_;
  CellFolders folders_;
  std::string output_root_;
  NodeDiagnostics diagnostics_;
  Server server_;
  ros::ServiceServer list_srv_, get_srv_;
  ros::WallTimer heartbeat_;
  PartClient parts_;  // only the worker uses it
  StageChain chain_{StageChainOptions{kServerWait}};  // only the worker uses it

  std::mutex mutex_;  // guards everything below
  std::condition_variable wake_;
  std::deque<GoalHandle> queue_;
  GoalHandle active_;
  bool running_ = false, finished_ = false, cancel_ = false, stopping_ = false;
  std::string stage_, timed_out_;
  Clock::time_point stage_start_, cancel_asked_, last_published_;
  PlanPartFeedback last_feedback_;
  std::thread worker_;
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 2 threads: goals, cancels, services and the heartbeat while the worker plans.
  return art2part::runNode<art2part::CellSupervisorNode>(argc, argv, "cell_supervisor", 2);
}
