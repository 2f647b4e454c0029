// part_server_node: loads part files and serves them to the other stages by id.
//   services: load_part (LoadPart), get_part (GetPart), list_parts (ListParts)
//   topics:   part (LoadedPart, latched: the part loaded last), part_marker (Marker, latched)
//             (part_marker: namespace "<part_id>/part" after a DELETEALL)
//   params:   ~part_file (load at start-up), ~frame_id (default "part")
// A bad request gets success=false and the reason; the node stays up.
#include <ros/ros.h>

#include <map>
#include <mutex>

#include <art2part/GetPart.h>
#include <art2part/ListParts.h>
#include <art2part/LoadPart.h>

#include "part_conversions.h"
#include "part_markers.h"
#include "marker_helpers.h"

namespace art2part {

class PartServer {
 public:
  explicit PartServer(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    pnh.param<std::string>("frame_id", frame_id_, "part");
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
    try {
      LoadOptions options;
      options.unit = parseLengthUnit(req.units);
      if (req.chordal_tolerance < 0.0) throw InputError("chordal_tolerance must not be negative");
      options.chordal_tolerance = req.chordal_tolerance / kMetresPerMm;
      Part part = loadPart(req.path, options);
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
    } catch (const std::exception& e) {  // InputError and anything a library threw: the node stays up
      res.success = false;
      res.message = e.what();
      ROS_WARN("load_part failed: %s", e.what());
    }
    return true;
  }

  bool get(GetPart::Request& req, GetPart::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string id = req.part_id.empty() ? last_id_ : req.part_id;
    auto it = parts_.find(id);
    if (it == parts_.end()) {
      res.success = false;
      res.message = "no part with id '" + id + "'" + (parts_.empty() ? " (no part loaded yet)" : "");
      return true;
    }
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
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& entry : parts_) res.part_ids.push_back(entry.first);
    return true;
  }

  std::string frame_id_;
  ros::Publisher part_pub_, marker_pub_;
  ros::ServiceServer load_srv_, get_srv_, list_srv_;
  std::mutex mutex_;
  std::map<std::string, LoadedPart> parts_;
  std::string last_id_;
};

}  // namespace art2part

int main(int argc, char** argv) {
  ros::init(argc, argv, "part_server");
  ros::NodeHandle nh, pnh("~");
  art2part::PartServer server(nh, pnh);
  ros::spin();
  return 0;
}
