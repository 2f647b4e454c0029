// The cell's pipeline through the stage nodes (stage_chain.h).
#include "stage_chain.h"

#include <art2part/PlanSetups.h>
#include <art2part/VerifyToolpaths.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "art2part/plan/stage_records.h"
#include "art2part/plan/useless_operations.h"
#include "setup_markers.h"  // visibilityFromMessage

namespace art2part {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string modeName(MachineMode mode) { return mode == MachineMode::FiveAxis ? "5axis" : "3axis"; }

}  // namespace

StageChain::StageChain(StageChainOptions options)
    : options_(options),
      visibility_("analyse_visibility", true),
      roughing_("plan_roughing", true),
      finishing_("plan_finishing", true) {}

// Sends the goal, forwards feedback, waits: a stop from the sink cancels the goal; a server that is not offered within
// server_wait_s, or whose node goes away while it works, fails the stage, as does a result without success.
template <class Action>
ResultPtrOf<Action> StageChain::callAction(
    actionlib::SimpleActionClient<Action>& client, const std::string& stage, const GoalOf<Action>& goal,
    const std::function<void(const FeedbackPtrOf<Action>&)>& on_feedback,
    const ProgressSink& progress, const std::function<bool()>& go_on) {
  const auto start = Clock::now();
  while (!client.waitForServer(ros::Duration(options_.poll_s))) {
    reportProgress(progress, stage, 0, "waiting for its node");
    if (!go_on()) throw StageStopped(stage);
    if (since(start) > options_.server_wait_s || !ros::ok())
      throw StageFailure(stage, "no node offers it (waited " + std::to_string(static_cast<int>(options_.server_wait_s)) +
                                    " s for its action)");
  }
  // Feedback comes on the client's thread, also after this call has given up on the goal: it passes through a gate
  // closed (under its lock) on every way out, so a late message never reaches the caller's finished sink.
  struct Gate {
    std::mutex mutex;
    std::function<void(const FeedbackPtrOf<Action>&)> forward;
  };
  auto gate = std::make_shared<Gate>();
  gate->forward = on_feedback;
  struct Closer {
    std::shared_ptr<Gate> gate;
    ~Closer() {
      std::lock_guard<std::mutex> lock(gate->mutex);
      gate->forward = nullptr;
    }
  } closer{gate};
  client.sendGoal(goal, {}, {}, [gate](const FeedbackPtrOf<Action>& f) {
    std::lock_guard<std::mutex> lock(gate->mutex);
    if (gate->forward) gate->forward(f);
  });
  while (!client.waitForResult(ros::Duration(options_.poll_s))) {
    if (!go_on()) {
      client.cancelGoal();
      throw StageStopped(stage);
    }
    if (!client.isServerConnected() || !ros::ok())
      throw StageFailure(stage, "its node went away while it worked (killed or crashed; a respawned node serves the "
                                "next goal)");
  }
  const auto result = client.getResult();
  if (!result || !result->success)
    throw StageFailure(stage, result ? result->message : client.getState().toString());
  return result;
}

// A service call on its own thread, so that a stop or a node that goes away ends the wait; an abandoned call finishes
// alone (its answer is dropped).
template <class Service>
Service StageChain::callService(const std::string& name, const std::string& stage, const Service& request,
                                const ProgressSink& progress, const std::function<bool()>& go_on) {
  const auto start = Clock::now();
  while (!ros::service::waitForService(name, ros::Duration(options_.poll_s))) {
    reportProgress(progress, stage, 0, "waiting for its node");
    if (!go_on()) throw StageStopped(stage);
    if (since(start) > options_.server_wait_s || !ros::ok())
      throw StageFailure(stage, "no node offers it (waited " + std::to_string(static_cast<int>(options_.server_wait_s)) +
                                    " s for " + name + ")");
  }
  struct Call {
    std::mutex mutex;
    std::condition_variable done_cv;
    bool done = false, ok = false;
    Service srv;
  };
  auto call = std::make_shared<Call>();
  call->srv = request;
  std::thread([call, name] {
    Service srv = call->srv;
    const bool ok = ros::service::call(name, srv);
    std::lock_guard<std::mutex> lock(call->mutex);
    call->srv = std::move(srv);
    call->ok = ok;
    call->done = true;
    call->done_cv.notify_all();
  }).detach();
  std::unique_lock<std::mutex> lock(call->mutex);
  while (!call->done_cv.wait_for(lock, std::chrono::duration<double>(options_.poll_s), [&] { return call->done; })) {
    lock.unlock();
    const bool going = go_on();
    lock.lock();
    if (!going) throw StageStopped(stage);
  }
  if (!call->ok) throw StageFailure(stage, "the call to " + name + " failed: its node went away while it worked");
  if (!call->srv.response.success) throw StageFailure(stage, call->srv.response.message);
  return call->srv;
}

PlanResult StageChain::run(const PlanPartGoal& goal, const std::string& part_id, const Part& part,
                           const ToolLibrary& library, const PlanOptions& options, const std::string& picture_file,
                           const ProgressSink& progress, const std::function<bool()>& go_on) {
  PlanResult plan;
  const auto all = Clock::now();
  auto timed = [&](const std::string& stage, Clock::time_point start) { plan.timings.emplace_back(stage, since(start)); };
  const std::string mode = modeName(options.setups.mode);

  auto start = Clock::now();
  AnalyseVisibilityGoal visibility_goal;
  visibility_goal.part_id = part_id;
  visibility_goal.level = options.visibility.level;
  visibility_goal.no_special_directions = !options.visibility.special_directions;
  visibility_goal.no_side_correction = !options.visibility.side_correction;
  const auto seen = callAction<AnalyseVisibilityAction>(
      visibility_, "visibility", visibility_goal,
      [&](const FeedbackPtrOf<AnalyseVisibilityAction>& f) { reportProgress(progress, "visibility", f->fraction, f->stage); },
      progress, go_on);
  plan.visibility = visibilityFromMessage(part, seen->directions, seen->bits, seen->special);
  timed("visibility", start);

  start = Clock::now();
  reportProgress(progress, "setups", 0, "minimum cover of the visibility cones");
  PlanSetups setups;
  setups.request.part_id = part_id;
  setups.request.mode = mode;
  setups.request.directions = seen->directions;
  setups.request.bits = seen->bits;
  setups.request.special = seen->special;
  setups.request.finishing_setups = options.finish;
  setups = callService("plan_setups", "setups", setups, progress, go_on);
  plan.setups = setupsFromRecord(setups.response.record);
  timed("setups", start);

  start = Clock::now();
  PlanRoughingGoal roughing_goal;
  roughing_goal.part_id = part_id;
  roughing_goal.mode = mode;
  roughing_goal.rest_pass = options.roughing.rest.enabled;
  roughing_goal.five_axis = options.roughing.five_axis.enabled;
  roughing_goal.setups_record = setups.response.record;
  roughing_goal.plug_holes = options.finish;
  const auto roughed = callAction<PlanRoughingAction>(
      roughing_, "roughing", roughing_goal,
      [&](const FeedbackPtrOf<PlanRoughingAction>& f) {
        reportProgress(progress, f->stage == "holes" ? "holes" : "roughing", f->fraction, f->operation);
      },
      progress, go_on);
  RoughingStage roughing = roughingFromRecord(roughed->record);
  plan.timings.emplace_back("holes", roughing.seconds_holes);
  plan.timings.emplace_back("roughing", since(start) - roughing.seconds_holes);
  plan.holes = roughing.holes;
  plan.hole_methods = roughing.hole_methods;
  plan.roughing = std::move(roughing.roughing);

  if (options.finish) {
    start = Clock::now();
    PlanFinishingGoal finishing_goal;
    finishing_goal.part_id = part_id;
    finishing_goal.mode = mode;
    finishing_goal.scallop_m = goal.scallop_m;  // as the goal gave it: the node converts it as planOptionsFrom does
    finishing_goal.directions = seen->directions;
    finishing_goal.bits = seen->bits;
    finishing_goal.special = seen->special;
    finishing_goal.setups_record = setups.response.record;
    finishing_goal.roughing_record = roughed->record;
    const auto finished = callAction<PlanFinishingAction>(
        finishing_, "finishing", finishing_goal,
        [&](const FeedbackPtrOf<PlanFinishingAction>& f) {
          reportProgress(progress, "finishing", f->fraction, f->message.empty() ? f->stage : f->message);
        },
        progress, go_on);
    plan.finishing = finishingFromRecord(finished->record);
    timed("finishing", start);
  }

  combinePlan(plan, part, library, options);
  if (options.verify && !plan.toolpath.empty()) {
    start = Clock::now();
    reportProgress(progress, "verification", 0, "simulating " + std::to_string(plan.toolpath.size()) + " moves");
    // The picture is of the plan verified last: when the plan without its useless roughing is not kept (it found more
    // than the plan with it), the picture shows that plan's stock.
    // The service sweeps the whole path: a trial's checkpoints and gate stay unused (the same decisions, slower).
    auto verify = [&](const PlanResult& p, VerificationState&, const TrialSweep&) {
      VerifyToolpaths call;
      call.request.part_id = part_id;
      call.request.toolpath_record = toolpathRecord(p.toolpath, p.tools);
      call.request.options_record = verifyOptionsRecord(planVerifyOptions(part, p, library, options));
      call.request.picture_file = picture_file;
      call = callService("verify_toolpaths", "verification", call, progress, go_on);
      return verificationFromRecord(call.response.record);
    };
    VerificationState unused;
    const std::vector<SweepCheckpoint> none;
    plan.verification = verify(plan, unused, TrialSweep{none, 0, {}});
    plan.verified = true;
    timed("verification", start);
    if (options.drop_useless) {
      start = Clock::now();
      dropUselessRoughing(plan, part, library, options, verify);
      if (plan.useless.found > 0) timed("verification without useless roughing", start);
    }
    judgeFaces(plan.verification, plan.finishing);
  }
  plan.timings.emplace_back("total", since(all));
  return plan;
}

}  // namespace art2part
