// part_server_node: loads part files and serves them to the other stages by id.
//   services: load_part (LoadPart), get_part (GetPart), list_parts (ListParts)
//   topics:   part (LoadedPart, latched: the part loaded last), part_marker (Marker, latched)
//             (part_marker: namespace "<part_id>/part" after a DELETEALL)
//   params:   ~part_file (load at start-up), ~frame_id (default "part"); /art2part/part_folders (cell_folders.h)
//   topics:   /diagnostics (node_diagnostics.h)
// A bad request gets success=false and the reason; the node stays up. load_part opens only files inside the part
// folders: any other path is refused before it is opened, with the same message whether it exists or not.
#include <ros/ros.h>

#include <map>
#include <mutex>

#include <art2part/GetPart.h>
#include <art2part/ListParts.h>
#include <art2part/LoadPart.h>

#include "node_main.h"
#include "art2part/common/request_limits.h"
#include "cell_folders.h"
#include "node_diagnostics.h"
#include "part_conversions.h"
#include "part_markers.h"
#include "marker_helpers.h"

namespace art2part {

class PartServer {
 public:
  explicit PartServer(ros::NodeHandle& nh, ros::NodeHandle& pnh) : folders_(readCellFolders(false)) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
    diagnostics_.setConfiguration("part folders", folderList(folders_.parts));
    for (const std::string& problem : folders_.problems) diagnostics_.addProblem(problem);
    part_pub_ = nh.advertise<LoadedPart>("part", 1, true);
    marker_pub_ = nh.advertise<visualization_msgs::Marker>("part_marker", 1, true);
    load_srv_ = nh.advertiseService("load_part", &PartServer::load, this);
    get_srv_ = nh.advertiseService("get_part", &PartServer::get, this);
    list_srv_ = nh.advertiseService("list_parts", &PartServer::list, this);
    std::string file;
    if (pnh.getParam("part_file", file) && !file.empty()) {
      LoadPart::Request req;
      LoadPart::Response res;
      req.path = file;
      load(req, res);
      if (res.success) ROS_INFO("loaded %s as '%s'", file.c_str(), res.part_id.c_str());
      else ROS_ERROR("%s", res.message.c_str());
    }
  }

 private:
  static std::string baseName(const std::string& path) {
    std::string name = path.substr(path.find_last_of('/') + 1);
    return name.substr(0, name.find_last_of('.'));
  }

  bool load(LoadPart::Request& req, LoadPart::Response& res) {
    NodeDiagnostics::Request request = diagnostics_.request("load_part");
    try {
      LoadOptions options;
      options.unit = parseLengthUnit(req.units);
      options.chordal_tolerance =
          checkedRequestValue(req.chordal_tolerance, request_limits::kChordalTolerance) / kMetresPerMm;
      const std::string path = confinedField(folders_.parts, "path", req.path);  // before anything is opened
      Part part = loadPart(path, options);
      const std::string id = req.part_id.empty() ? baseName(req.path) : req.part_id;
      LoadedPart msg = toMsg(part, id);
      res.summary = msg.summary;
      res.part_id = id;
      res.success = true;
      for (const std::string& w : msg.summary.warnings) res.message += (res.message.empty() ? "" : "; ") + w;
      part_pub_.publish(msg);
      marker_pub_.publish(deleteAllMarker(frame_id_));  // the part loaded before leaves rviz
      marker_pub_.publish(partMarker(part, frame_id_, partNamespace(id, "part")));
      std::lock_guard<std::mutex> lock(mutex_);
      parts_[id] = std::move(msg);
      last_id_ = id;
      request.finish(RequestOutcome::Served, "'" + id + "' from " + path);
    } catch (const std::exception& e) {  // InputError and anything a library threw: the node stays up
      res.success = false;
      res.message = e.what();
      ROS_WARN("load_part failed: %s", e.what());
      request.finish(outcomeOf(e), e.what());
    }
    return true;
  }

  // Serves only parts loaded through load_part (so only files from the part folders).
  bool get(GetPart::Request& req, GetPart::Response& res) {
    NodeDiagnostics::Request request = diagnostics_.request("get_part");
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string id = req.part_id.empty() ? last_id_ : req.part_id;
    auto it = parts_.find(id);
    if (it == parts_.end()) {
      res.success = false;
      res.message = "no part with id '" + id + "'" + (parts_.empty() ? " (no part loaded yet)" : "");
      request.finish(RequestOutcome::Refused, res.message);
      return true;
    }
    request.finish(RequestOutcome::Served, "'" + id + "'");
    res.success = true;
    if (req.summary_only) {
      res.part.id = it->second.id;
      res.part.source = it->second.source;
      res.part.summary = it->second.summary;
    } else {
      res.part = it->second;
    }
    return true;
  }

  bool list(ListParts::Request&, ListParts::Response& res) {
    NodeDiagnostics::Request request = diagnostics_.request("list_parts");
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& entry : parts_) res.part_ids.push_back(entry.first);
    request.finish(RequestOutcome::Served, std::to_string(res.part_ids.size()) + " parts");
    return true;
  }

  const CellFolders folders_;
  NodeDiagnostics diagnostics_;
  std::string frame_id_;
  ros::Publisher part_pub_, marker_pub_;
  ros::ServiceServer load_srv_, get_srv_, list_srv_;
  std::mutex mutex_;
  std::map<std::string, LoadedPart> parts_;
  std::string last_id_;
};

}  // namespace art2part

int main(int argc, char** argv) { return art2part::runNode<art2part::PartServer>(argc, argv, "part_server", 1); }
