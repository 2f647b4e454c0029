// verification_node: checks any plan folder (toolpaths.csv + tools.json, ours or a third party's) against its part by
// simulating the stock (issue 5), for the supervisor and for a cell operator. The same steps as `art2part verify`.
//   service:  verify_toolpaths (VerifyToolpaths): gouges, collisions, leftover and the whole JSON report, of a plan
//             folder, or of a plan handed on as records on a part in part_server (the cell supervisor's chain: the
//             path and the plan's verify options; picture_file gets remaining.png), the report also as a record
//   topics:   verification_markers (MarkerArray, latched): DELETEALL, the remaining stock coloured by deviation,
//             gouges (red) and collisions (orange) as spheres, in ~frame_id (default "part"), metres
//             (markers: namespace under "<part_id>/" (the part file's or the folder's name), a DELETEALL first)
//   params:   ~frame_id, ~marker_cells (cells along the stock's longest side for the stock mesh; default 150);
//             /art2part/output_root, /art2part/part_folders (cell_folders.h)
//   topics:   /diagnostics (node_diagnostics.h)
// Bad input (missing folder, malformed file, unknown tool, bad numbers) answers success=false with the reason; the node
// stays up. The folder must lie under the output root, the part file in a part folder or under the output root (a
// plan's mesh.stl); any other path is refused before it is opened. A path that gouges or collides is success=true,
// passed=false. Requests run in parallel (AsyncSpinner); when they finish out of order, the markers shown are those
// of the most recent request.
#include <ros/ros.h>

#include <atomic>
#include <chrono>
#include <mutex>

#include "node_main.h"
#include "art2part/plan/plan_pictures.h"
#include "cell_folders.h"
#include "part_client.h"
#include "node_diagnostics.h"
#include "verification_markers.h"
#include "marker_helpers.h"

namespace art2part {

class VerificationNode {
 public:
  VerificationNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : folders_(readCellFolders(false)) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
    diagnostics_.setConfiguration("output root", folderList(folders_.plans));
    diagnostics_.setConfiguration("part folders", folderList(folders_.parts));
    for (const std::string& problem : folders_.problems) diagnostics_.addProblem(problem);
    pnh.param("marker_cells", marker_cells_, 150);
    if (marker_cells_ < 8) marker_cells_ = 8;
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("verification_markers", 1, true);
    service_ = nh.advertiseService("verify_toolpaths", &VerificationNode::verify, this);
  }

 private:
  bool verify(VerifyToolpaths::Request& req, VerifyToolpaths::Response& res) {
    const auto start = std::chrono::steady_clock::now();
    const long ticket = ++requests_;
    NodeDiagnostics::Request request = diagnostics_.request("verify_toolpaths");
    try {
      FolderVerification v;
      std::string part_id;  // the markers' namespace
      if (req.toolpath_record.empty()) {
        verifyFolder(confined(req), v);
        res.message = "'" + req.folder + "' on '" + partFileOf(req) + "': " + summaryOf(v.report);
        part_id = partIdOfFile(req.part_file.empty() ? req.folder : req.part_file);
      } else {
        const std::string picture = req.picture_file.empty() ? "" : confinedField(folders_.plans, "picture_file", req.picture_file);
        verifyHandedOn(req, *part(req.part_id, part_id), v);
        if (!picture.empty()) writeRemainingPicture(v.part, v.report, v.state, picture);
        res.message = "the plan handed on for '" + part_id + "': " + summaryOf(v.report);
      }
      fillResponse(v.report, res);
      res.success = true;
      publish(ticket, part_id, v);
      ROS_INFO("verify_toolpaths: %s", res.message.c_str());
      request.finish(RequestOutcome::Served, res.message);
    } catch (const std::exception& e) {  // InputError (a bad request) and anything else: an answer, not a crash
      res = VerifyToolpaths::Response();
      res.success = false;
      res.message = e.what();
      ROS_WARN("verify_toolpaths: %s", e.what());
      request.finish(outcomeOf(e), e.what());
    }
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return true;
  }

  // The part loaded in part_server (PartClient's cache is not thread-safe; requests run in parallel).
  std::shared_ptr<const Part> part(const std::string& requested, std::string& id) {
    std::lock_guard<std::mutex> lock(parts_mutex_);
    return parts_.get(requested, &id);
  }

  // The request with its folder and part file resolved inside the configured folders (refused otherwise).
  VerifyToolpaths::Request confined(const VerifyToolpaths::Request& req) const {
    VerifyToolpaths::Request out = req;
    out.folder = confinedField(folders_.plans, "folder", req.folder);
    out.part_file = confinedField(folders_.part_files, "part_file", partFileOf(out));  // default: folder/mesh.stl
    return out;
  }

  // The markers are made outside the lock (contouring takes a while), and published unless a later request has been.
  void publish(long ticket, const std::string& part_id, const FolderVerification& v) {
    if (ticket < shown_ticket_.load()) return;
    const visualization_msgs::MarkerArray markers =
        forPart(part_id, verificationMarkers(remainingStock(v, marker_cells_), v.report, frame_id_));
    std::lock_guard<std::mutex> lock(publish_mutex_);
    if (ticket < shown_ticket_.load()) return;
    shown_ticket_ = ticket;
    markers_pub_.publish(markers);
  }

  const CellFolders folders_;
  NodeDiagnostics diagnostics_;
  std::string frame_id_;
  int marker_cells_ = 150;
  ros::Publisher markers_pub_;
  ros::ServiceServer service_;
  std::mutex publish_mutex_, parts_mutex_;
  PartClient parts_;
  std::atomic<long> requests_{0}, shown_ticket_{0};
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 2 threads: a bad request is answered while a verification runs.
  return art2part::runNode<art2part::VerificationNode>(argc, argv, "verification", 2);
}
