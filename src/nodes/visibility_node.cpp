// visibility_node: visibility cones of a part loaded in part_server (thesis 3.2).
//   action:   analyse_visibility (AnalyseVisibility): progress feedback, directions and the packed bit matrix
//   service:  show_cone (ShowCone): publish the cone of one triangle or face of the last analysis
//   topics:   visibility_markers (MarkerArray, latched): direction sphere and part coloured by cone size;
//             cone_marker (Marker, latched); /diagnostics (node_diagnostics.h)
//             (markers: every namespace under "<part_id>/", a DELETEALL first; marker_helpers' forPart)
// A bad goal is aborted with the reason; the node stays up.
#include <actionlib/server/simple_action_server.h>
#include <ros/ros.h>

#include <art2part/AnalyseVisibilityAction.h>
#include <art2part/ShowCone.h>

#include <chrono>
#include <cstring>
#include <mutex>

#include "node_main.h"
#include "art2part/common/request_limits.h"
#include "node_diagnostics.h"
#include "stage_goals.h"
#include "part_client.h"
#include "visibility_markers.h"
#include "marker_helpers.h"

namespace art2part {

class VisibilityNode {
 public:
  VisibilityNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : server_(nh, "analyse_visibility", [this](const AnalyseVisibilityGoalConstPtr& goal) { execute(goal); }, false) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("visibility_markers", 1, true);
    cone_pub_ = nh.advertise<visualization_msgs::Marker>("cone_marker", 1, true);
    cone_srv_ = nh.advertiseService("show_cone", &VisibilityNode::showCone, this);
    server_.start();
  }

 private:
  static VisibilityOptions optionsFrom(const AnalyseVisibilityGoal& goal) {
    VisibilityOptions options;
    if (checkedRequestValue(goal.level, request_limits::kSphereLevel) != 0) options.level = goal.level;
    options.special_directions = !goal.no_special_directions;
    options.side_correction = !goal.no_side_correction;
    if (!goal.backend.empty()) options.backend = parseVisibilityBackend(goal.backend);
    options.render.resolution =
        static_cast<int>(checkedRequestValue(goal.resolution, request_limits::kRenderResolution));
    return options;
  }

  void fillResult(const VisibilityResult& r, AnalyseVisibilityResult& out) {
    out.triangle_count = r.map.triangles();
    for (int d = 0; d < r.directions.size(); ++d) {
      geometry_msgs::Vector3 v;
      v.x = r.directions.directions[d].x();
      v.y = r.directions.directions[d].y();
      v.z = r.directions.directions[d].z();
      out.directions.push_back(v);
      out.special.push_back(static_cast<uint8_t>(r.directions.special[d]));
    }
    const int bytes = (r.map.directions() + 7) / 8;
    out.bits.resize(static_cast<std::size_t>(bytes) * r.map.triangles());
    for (int t = 0; t < r.map.triangles(); ++t)
      std::memcpy(&out.bits[static_cast<std::size_t>(t) * bytes], r.map.bits.row(t), bytes);  // little-endian words
    out.cone_solid_angle = coneSolidAngles(r.map, r.directions);
    out.unseen_triangles.assign(r.unseen_triangles.begin(), r.unseen_triangles.end());
  }

  void execute(const AnalyseVisibilityGoalConstPtr& goal) {
    AnalyseVisibilityResult result;
    const auto start = std::chrono::steady_clock::now();
    NodeDiagnostics::Request request = diagnostics_.request("analyse_visibility");
    try {
      const VisibilityOptions options = optionsFrom(*goal);
      AnalyseVisibilityFeedback feedback;
      feedback.stage = "fetching part";
      server_.publishFeedback(feedback);
      std::string id;
      auto part = parts_.get(goal->part_id, &id);
      feedback.stage = "visibility";
      auto progress = [this, &feedback](const ProgressReport& p) {
        feedback.fraction = p.fraction;
        server_.publishFeedback(feedback);
        return !cancelAsked(server_) && ros::ok();
      };
      auto analysis = std::make_shared<VisibilityResult>(analyseVisibility(*part, options, progress));
      if (analysis->cancelled) throw std::runtime_error("cancelled");  // ends preempted below
      fillResult(*analysis, result);
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      result.success = true;
      result.message = "part '" + id + "': " + std::to_string(analysis->map.triangles()) + " triangles x " +
                       std::to_string(analysis->map.directions()) + " directions, " +
                       std::to_string(analysis->unseen_triangles.size()) + " triangles seen from nowhere";
      markers_pub_.publish(forPart(id, visibilityMarkers(*part, *analysis, frame_id_)));
      {
        const std::lock_guard<std::mutex> lock(last_mutex_);
        last_part_ = part;
        last_id_ = id;
        last_ = analysis;
      }
      server_.setSucceeded(result);
      request.finish(RequestOutcome::Served, result.message);
    } catch (const std::exception& e) {
      result.success = false;
      result.message = e.what();
      ROS_WARN("analyse_visibility: %s", e.what());
      const bool preempted = cancelAsked(server_);
      if (preempted) server_.setPreempted(result, e.what());
      else server_.setAborted(result, e.what());
      request.finish(preempted ? RequestOutcome::Cancelled : outcomeOf(e), e.what());
    }
  }

  bool showCone(ShowCone::Request& req, ShowCone::Response& res) {
    NodeDiagnostics::Request request = diagnostics_.request("show_cone");
    {
      const std::lock_guard<std::mutex> lock(last_mutex_);  // an analysis may be ending on the other thread
      coneOf(req, res);
    }
    request.finish(res.success ? RequestOutcome::Served : RequestOutcome::Refused, res.message);
    return true;
  }

  bool coneOf(ShowCone::Request& req, ShowCone::Response& res) {
    if (!last_) {
      res.success = false;
      res.message = "no visibility analysis yet";
      return true;
    }
    const Part& part = *last_part_;
    std::vector<int> triangles;
    if (req.triangle >= 0) {
      if (req.triangle >= part.mesh.triangleCount()) {
        res.message = "triangle " + std::to_string(req.triangle) + " out of range (the part has " +
                      std::to_string(part.mesh.triangleCount()) + ")";
        return true;
      }
      triangles.push_back(req.triangle);
    } else if (req.face >= 0 && req.face < static_cast<int>(part.faces.size())) {
      for (int t = 0; t < part.mesh.triangleCount(); ++t)
        if (part.triangle_face[t] == req.face) triangles.push_back(t);
    } else {
      res.message = "name a triangle or a face in range (the part has " + std::to_string(part.faces.size()) + " faces)";
      return true;
    }
    const Cone cone = commonCone(last_->map, triangles);
    Vec3 apex = Vec3::Zero();
    for (int t : triangles) apex += triangleCentroid(part.mesh, t) / static_cast<double>(triangles.size());
    visualization_msgs::Marker cone_marker = coneMarker(part, *last_, cone, apex, frame_id_);
    cone_marker.ns = partNamespace(last_id_, cone_marker.ns);
    cone_pub_.publish(deleteAllMarker(frame_id_));  // the cone shown before goes, whichever part it was on
    cone_pub_.publish(cone_marker);
    res.success = true;
    res.directions_in_cone = coneSize(cone);
    res.solid_angle = coneSolidAngle(cone, last_->directions);
    return true;
  }

  NodeDiagnostics diagnostics_;
  actionlib::SimpleActionServer<AnalyseVisibilityAction> server_;
  std::string frame_id_;
  ros::Publisher markers_pub_, cone_pub_;
  ros::ServiceServer cone_srv_;
  PartClient parts_;
  std::shared_ptr<const Part> last_part_;
  std::string last_id_;  // the part id of last_part_
  std::shared_ptr<const VisibilityResult> last_;
  std::mutex last_mutex_;  // over last_part_, last_id_ and last_
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 2 threads: show_cone answers while an analysis runs.
  return art2part::runNode<art2part::VisibilityNode>(argc, argv, "visibility", 2);
}
