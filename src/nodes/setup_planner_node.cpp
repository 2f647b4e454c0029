// setup_planner: the fewest setups that machine a part loaded in part_server (thesis 3.3).
//   service:  plan_setups (PlanSetups): analyses visibility here with the request's options, or plans on the
//             directions + bits of an analyse_visibility result passed in the request; with finishing_setups,
//             also the setups finishing adds (planPartSetups, as `art2part plan`); the response's record holds the
//             whole plan for plan_roughing and plan_finishing (stage_records.h)
//   params:   ~frame_id, ~unused_frame_id, ~tools (the tool library for finishing_setups; default config/tools.yaml)
//   tf2:      static transforms part -> setup_<k>, one per setup of the last plan. A static transform cannot be
//             withdrawn: when a plan has fewer setups than one before it, the leftover setup_<k> are re-sent under
//             the parameter ~unused_frame_id (default "unused_setups", a frame with no parent), so looking them up
//             from part fails instead of showing an old plan.
//   topics:   setup_markers (MarkerArray, latched): DELETEALL, an arrow and a label per setup, the part by setup;
//             /diagnostics (node_diagnostics.h)
//             (markers: every namespace under "<part_id>/", a DELETEALL first; marker_helpers' forPart)
// A bad request answers success=false with the reason; the node stays up. Requests run in parallel (AsyncSpinner);
// when plans finish out of order, the markers and frames shown are those of the most recent request.
#include "node_main.h"
#include "setup_markers.h"  // first: it renames the message art2part::Setup (see there)

#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <atomic>
#include <chrono>
#include <mutex>

#include "art2part/plan/stage_records.h"
#include "node_diagnostics.h"
#include "part_client.h"
#include "marker_helpers.h"

#ifndef ART2PART_CONFIG_DIR
#error "ART2PART_CONFIG_DIR (the package's config folder) must be defined by the build"
#endif

namespace art2part {

class SetupPlannerNode {
 public:
  SetupPlannerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
    pnh.param<std::string>("unused_frame_id", unused_frame_id_, "unused_setups");
    pnh.param<std::string>("tools", tools_path_, std::string(ART2PART_CONFIG_DIR) + "/tools.yaml");
    diagnostics_.setConfiguration("tools", tools_path_);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("setup_markers", 1, true);
    service_ = nh.advertiseService("plan_setups", &SetupPlannerNode::plan, this);
  }

 private:
  bool plan(PlanSetups::Request& req, PlanSetups::Response& res) {
    const auto start = std::chrono::steady_clock::now();
    const long ticket = ++requests_;
    NodeDiagnostics::Request request = diagnostics_.request("plan_setups");
    try {
      const SetupOptions options = setupOptionsFrom(req);
      const bool given = carriesVisibility(req);
      const VisibilityOptions visibility_options = given ? VisibilityOptions{} : visibilityOptionsFrom(req);
      std::string id;
      std::shared_ptr<const Part> part;
      {
        std::lock_guard<std::mutex> lock(parts_mutex_);  // PartClient's cache is not thread-safe
        part = parts_.get(req.part_id, &id);
      }
      const VisibilityResult visibility =
          given ? visibilityFromRequest(*part, req) : analyseVisibility(*part, visibility_options);
      PlanOptions plan_options;  // the setups of `art2part plan`: the cover, and those finishing adds when asked
      plan_options.setups = options;
      plan_options.finish = req.finishing_setups;
      const SetupPlan plan = req.finishing_setups
                                 ? planPartSetups(*part, visibility, loadToolLibrary(tools_path_), plan_options)
                                 : planSetups(*part, visibility, options);
      fillResponse(plan, visibility.directions, res);
      res.record = setupsRecord(plan);
      res.success = true;
      res.message = "part '" + id + "': " + std::to_string(plan.setups.size()) +
                    (plan.setups.size() == 1 ? " setup (" : " setups (") + res.mode +
                    (plan.proven_minimal ? ", proven minimal" : ", best found in the time limit") + "; greedy " +
                    std::to_string(plan.greedy_setups) + "), " + std::to_string(plan.unmachinable_triangles.size()) +
                    " unmachinable triangles; " + std::to_string(visibility.map.triangles()) + " triangles x " +
                    std::to_string(visibility.map.directions()) + " directions " +
                    (given ? "from the request" : "analysed here");
      publish(ticket, id, *part, plan, res.setups);
      request.finish(RequestOutcome::Served, res.message);
    } catch (const std::exception& e) {  // InputError (a bad request) and anything else: an answer, not a crash
      res = PlanSetups::Response();
      res.success = false;
      res.message = e.what();
      ROS_WARN("plan_setups: %s", e.what());
      request.finish(outcomeOf(e), e.what());
    }
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return true;
  }

  void publish(long ticket, const std::string& part_id, const Part& part, const SetupPlan& plan,
               const std::vector<MachiningSetup>& setups) {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    if (ticket < shown_ticket_) return;  // a later request has been shown already
    shown_ticket_ = ticket;
    tf_.sendTransform(setupTransforms(setups, frames_sent_, frame_id_, unused_frame_id_, ros::Time::now()));
    frames_sent_ = std::max(frames_sent_, static_cast<int>(setups.size()));
    markers_pub_.publish(forPart(part_id, setupMarkers(part, plan, frame_id_)));
  }

  NodeDiagnostics diagnostics_;
  std::string frame_id_, unused_frame_id_, tools_path_;
  ros::Publisher markers_pub_;
  ros::ServiceServer service_;
  tf2_ros::StaticTransformBroadcaster tf_;
  std::mutex parts_mutex_, publish_mutex_;
  PartClient parts_;
  std::atomic<long> requests_{0};
  long shown_ticket_ = 0;
  int frames_sent_ = 0;  // setup_<k> frames ever sent: all re-sent each time (the broadcaster's latched list)
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 2 threads: a bad request is answered while a plan runs.
  return art2part::runNode<art2part::SetupPlannerNode>(argc, argv, "setup_planner", 2);
}
